// sobol::sample_table: eight samples at a time, their 64-bit hashes in one AVX-512 register
// (the DQ extension's 64-bit multiply) and their 32-bit arithmetic in one AVX2 register
// (permutation by cycle walking with a per-lane loop mask, Owen scrambling, bit reversal,
// the second dimension by four table gathers). Builds without AVX-512 (F, DQ, CD, VL) run the
// scalar twin.
#include <immintrin.h>

#include "sobol_net.h"
#include "sobol_simd.h"

namespace foton::kern::sobol {

#if FOTON_SOBOL_SIMD
namespace {
using namespace sobol_simd;

// permute(i, n, pk) of eight samples.
inline __m256i permute_lanes(__m256i i, __m256i n, __m512i pk) {
    const __m256i one = _mm256_set1_epi32(1);
    __m256i mask = _mm256_sub_epi32(n, one);
    for (int s = 1; s < 32; s <<= 1) mask = _mm256_or_si256(mask, _mm256_srli_epi32(mask, s));
    const __m512i h = mix(pk);
    const __m256i a = _mm256_or_si256(low32(h), one), c = low32(shr64(h, 32));
    const __m256i a2 = _mm256_or_si256(low32(shr64(h, 16)), one);
    // countr_one(mask) / 2, at least 1: mask is 2^k - 1, so k = 32 - lzcnt(mask).
    const __m256i k = _mm256_sub_epi32(_mm256_set1_epi32(32), _mm256_lzcnt_epi32(mask));
    const __m256i shift = _mm256_max_epi32(_mm256_srli_epi32(k, 1), one);
    // n <= 1: element 0; the others walk until they fall inside [0, n).
    const __mmask8 trivial = _mm256_cmple_epu32_mask(n, one);
    __mmask8 walking = __mmask8(~trivial);
    while (walking) {
        __m256i x = _mm256_and_si256(_mm256_add_epi32(_mm256_mullo_epi32(i, a), c), mask);
        x = _mm256_xor_si256(x, _mm256_srlv_epi32(x, shift));
        x = _mm256_and_si256(_mm256_mullo_epi32(x, a2), mask);
        x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 1));
        i = _mm256_mask_blend_epi32(walking, i, x);
        walking = walking & _mm256_cmpge_epu32_mask(i, n);
    }
    return _mm256_mask_blend_epi32(trivial, i, _mm256_setzero_si256());
}

}  // namespace

void sample_table(uint64_t seed, const uint32_t* index, const uint32_t* count, const uint64_t* key,
                  std::size_t n, const uint32_t* pairs, std::size_t n_pairs, float* out,
                  std::size_t stride) {
    for (std::size_t s = 0; s < n; s += 8) {
        const __m256i i = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(index + s));
        const __m256i cnt = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(count + s));
        const __m512i k = _mm512_loadu_si512(key + s);
        for (std::size_t p = 0; p < n_pairs; ++p) {
            const __m512i pk =
                mix(_mm512_xor_si512(k, _mm512_set1_epi64(int64_t(pair_salt(seed, pairs[p])))));
            const __m256i j = permute_lanes(i, cnt, pk);
            // x: owen_scramble(dim0(j)) starts by reversing dim0(j), which is j itself.
            const __m256i x = owen_reversed(j, _mm512_add_epi64(pk, _mm512_set1_epi64(1)));
            const __m256i y = owen_reversed(bit_reverse(dim1_lanes(j)),
                                            _mm512_add_epi64(pk, _mm512_set1_epi64(2)));
            _mm256_storeu_ps(out + 2 * p * stride + s, unit_float(x));
            _mm256_storeu_ps(out + (2 * p + 1) * stride + s, unit_float(y));
        }
    }
}
#else
void sample_table(uint64_t seed, const uint32_t* index, const uint32_t* count, const uint64_t* key,
                  std::size_t n, const uint32_t* pairs, std::size_t n_pairs, float* out,
                  std::size_t stride) {
    sample_table_scalar(seed, index, count, key, (n + 7) / 8 * 8, pairs, n_pairs, out, stride);
}
#endif

}  // namespace foton::kern::sobol
