// halton::sample_table: eight points at a time. The scalar code's arithmetic lane for lane:
// the scramble key's 64-bit hashes, each digit by division in doubles (exact: the quotient's
// fraction is a multiple of 1 / b, far above the rounding error of an index below 2^32), the
// digit's permutation a d + c mod b from the hash of the digits above it, the weighted sum in
// doubles in the same order. Base 2 is the Sobol' kernel's Owen scramble of the bit reversal.
// Builds without AVX-512 (F, DQ, CD, VL) run the scalar twin.
#include "counter_hash.h"
#include "halton_net.h"
#include "sobol_simd.h"

namespace foton::kern::halton {

#if FOTON_SOBOL_SIMD
namespace {

using namespace sobol_simd;
constexpr __mmask8 kAll8 = 0xff;

inline __m512i set64(uint64_t v) {
    return _mm512_set1_epi64(int64_t(v));
}
inline __m512d floor_pd(__m512d x) {
    return _mm512_mask_roundscale_pd(x, kAll8, x, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
}
inline __m512d to_double(__m512i v) {
    return _mm512_maskz_cvtepu64_pd(kAll8, v);
}
inline __m512i to_u64(__m512d v) {
    return _mm512_maskz_cvttpd_epu64(kAll8, v);
}

// scrambled_radical_inverse for eight indices i (doubles) in base b > 2, keyed by `scramble`.
__m256 radical_inverse_lanes(__m512d i, uint32_t b, __m512i scramble) {
    const double inv = 1.0 / b;
    constexpr double kFinest = 1.0 / double(1u << 25);
    const __m512d base = _mm512_set1_pd(double(b)), zero = _mm512_setzero_pd();
    const __m512i low = set64(0xffffffffull);
    __m512d r = zero;
    __m512i prefix = mix(scramble);
    for (double f = inv; f > kFinest; f *= inv) {
        const __m512d q = floor_pd(_mm512_div_pd(i, base));
        const __m512d d = _mm512_sub_pd(i, _mm512_mul_pd(q, base));
        i = q;
        // a = 1 + (lo (b - 1) >> 32), c = hi b >> 32, from the prefix's halves.
        const __m512i lo = _mm512_and_si512(prefix, low);
        const __m512i hi = shr64(prefix, 32);
        const __m512i a =
            _mm512_add_epi64(set64(1), shr64(_mm512_maskz_mul_epu32(kAll8, lo, set64(b - 1)), 32));
        const __m512i c = shr64(_mm512_maskz_mul_epu32(kAll8, hi, set64(b)), 32);
        const __m512i di = to_u64(d);
        // (a d + c) mod b, small enough for doubles to divide exactly.
        const __m512d x = to_double(_mm512_add_epi64(_mm512_mullo_epi64(a, di), c));
        const __m512d m = _mm512_sub_pd(x, _mm512_mul_pd(floor_pd(_mm512_div_pd(x, base)), base));
        const __mmask8 zero_digit = _mm512_cmpeq_epi64_mask(di, _mm512_setzero_si512());
        const __m512d perm = _mm512_mask_blend_pd(zero_digit, m, to_double(c));
        r = _mm512_add_pd(r, _mm512_mul_pd(perm, _mm512_set1_pd(f)));
        prefix = mix(_mm512_xor_si512(prefix, _mm512_add_epi64(di, set64(0x9e3779b97f4a7c15ull))));
    }
    // Below 1 even where every scrambled digit is b - 1.
    const __mmask8 below = _mm512_cmp_pd_mask(r, _mm512_set1_pd(1.0), _CMP_LT_OQ);
    r = _mm512_mask_blend_pd(below, _mm512_set1_pd(double(0x1.fffffep-1f)), r);
    return _mm512_maskz_cvtpd_ps(kAll8, r);
}

}  // namespace

void sample_table(uint64_t seed, const uint32_t* index, const uint64_t* key, std::size_t n,
                  const uint32_t* dims, std::size_t n_dims, float* out, std::size_t stride) {
    // stream_prefix(seed, key): its seed half once.
    const uint64_t seed_mix = mix64(seed + 0x9e3779b97f4a7c15ull);
    for (std::size_t s = 0; s < n; s += 8) {
        const __m256i idx32 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(index + s));
        const __m512i idx = _mm512_maskz_cvtepu32_epi64(kAll8, idx32);
        const __m512i k = _mm512_loadu_si512(key + s);
        const __m512i prefix = mix(
            _mm512_xor_si512(set64(seed_mix), _mm512_add_epi64(k, set64(0x632be59bd9b4e019ull))));
        const __m512d i_d = to_double(idx);
        for (std::size_t d = 0; d < n_dims; ++d) {
            const uint32_t dim = dims[d];
            if (dim >= kDims) {
                sample_table_scalar(seed, index + s, key + s, 8, dims + d, 1, out + d * stride + s,
                                    stride);
                continue;
            }
            // hash_from(prefix, dim, 0x4a19).
            const __m512i scramble = mix(_mm512_xor_si512(
                mix(_mm512_xor_si512(prefix, set64(dim + 0x85157af5ull * (0x4a19ull + 1)))),
                set64(0x4a19)));
            const uint32_t b = prime(dim);
            const __m256 v = b == 2 ? unit_float(owen_reversed(idx32, scramble))
                                    : radical_inverse_lanes(i_d, b, scramble);
            _mm256_storeu_ps(out + d * stride + s, v);
        }
    }
}
#else
void sample_table(uint64_t seed, const uint32_t* index, const uint64_t* key, std::size_t n,
                  const uint32_t* dims, std::size_t n_dims, float* out, std::size_t stride) {
    sample_table_scalar(seed, index, key, (n + 7) / 8 * 8, dims, n_dims, out, stride);
}
#endif

}  // namespace foton::kern::halton
