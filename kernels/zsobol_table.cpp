// zsobol::sample_table: eight samples at a time. The digit permutation runs in 64-bit lanes,
// one base-4 digit per step from the top, with a lane mask where the samples' index lengths
// (and so the positions of their digits) differ; the 24 permutations come by a gather. The
// Owen scramble and the generator matrices are the Sobol' kernel's (sobol_simd.h). Builds
// without AVX-512 (F, DQ, CD, VL) run the scalar twin.
#include <algorithm>

#include "sobol_simd.h"
#include "zsobol_net.h"

namespace foton::kern::zsobol {

#if FOTON_SOBOL_SIMD
namespace {
using namespace sobol_simd;

inline __m512i set64(uint64_t v) {
    return _mm512_set1_epi64(int64_t(v));
}
inline __m512i shr64v(__m512i z, __m512i n) {
    return _mm512_maskz_srlv_epi64(__mmask8(0xff), z, n);
}
inline __m512i shl64v(__m512i z, __m512i n) {
    return _mm512_maskz_sllv_epi64(__mmask8(0xff), z, n);
}

// The 24 permutations of four digits as one string of 192 bits (entry d of permutation k at
// bits 8 k + 2 d), in three broadcast words.
struct PackedPermutations {
    __m512i w0, w1, w2;
};
const PackedPermutations& packed_permutations() {
    static const PackedPermutations t = [] {
        uint64_t w[3] = {0, 0, 0};
        for (uint32_t k = 0; k < 24; ++k) w[k / 8] |= uint64_t(permutations()[k]) << (8 * (k % 8));
        return PackedPermutations{set64(w[0]), set64(w[1]), set64(w[2])};
    }();
    return t;
}

// permute_digits of eight samples: index, bit count (64-bit lanes), pair key.
__m512i permute_lanes(__m512i index, __m512i bits, __m512i pk, uint32_t max_bits, int step) {
    const PackedPermutations& table = packed_permutations();
    const __m512i three = set64(3), one = set64(1);
    const __m512i lone = _mm512_and_si512(bits, one);
    __m512i out = _mm512_setzero_si512();
    // Lanes of one parity (the usual case: one image, one sample count) have digits only at
    // every other position.
    for (int shift = int(max_bits) - 2; shift >= 0; shift -= step) {
        // The lanes with a digit at this position: below their top, of their parity.
        const __mmask8 active = _mm512_cmpge_epu64_mask(bits, set64(uint64_t(shift) + 2)) &
                                _mm512_cmpeq_epi64_mask(lone, set64(uint64_t(shift) & 1u));
        if (!active) continue;
        const __m512i above = shr64v(index, set64(uint64_t(shift) + 2));
        __m512i h = _mm512_mullo_epi64(
            _mm512_xor_si512(above,
                             _mm512_add_epi64(pk, set64(uint64_t(shift) * 0x9e3779b97f4a7c15ull))),
            set64(0xbf58476d1ce4e5b9ull));
        h = _mm512_xor_si512(h, shr64(h, 29));
        // which = (h >> 32) * 24 >> 32, the multiply as two shifts.
        const __m512i hi = shr64(h, 32);
        const __m512i which = shr64(_mm512_add_epi64(shl64(hi, 4), shl64(hi, 3)), 32);
        // Entry `digit` of permutation `which`: two bits at 8 which + 2 digit of the packed
        // table (three words), without a gather.
        const __m512i digit = _mm512_and_si512(shr64v(index, set64(uint64_t(shift))), three);
        const __m512i pos = _mm512_add_epi64(shl64(which, 3), _mm512_add_epi64(digit, digit));
        const __m512i word = shr64(pos, 6);
        __m512i packed =
            _mm512_mask_blend_epi64(_mm512_cmpeq_epi64_mask(word, one), table.w0, table.w1);
        packed = _mm512_mask_blend_epi64(_mm512_cmpeq_epi64_mask(word, set64(2)), packed, table.w2);
        const __m512i moved =
            _mm512_and_si512(shr64v(packed, _mm512_and_si512(pos, set64(63))), three);
        out = _mm512_mask_or_epi64(out, active, out, shl64v(moved, set64(uint64_t(shift))));
    }
    // A lone lowest bit, flipped by a hash.
    const __m512i h =
        _mm512_mullo_epi64(_mm512_xor_si512(shr64(index, 1), pk), set64(0x94d049bb133111ebull));
    const __m512i flip = _mm512_xor_si512(_mm512_and_si512(index, one), shr64(h, 63));
    return _mm512_mask_or_epi64(out, _mm512_test_epi64_mask(lone, lone), out, flip);
}

}  // namespace

void sample_table(const uint64_t* index, const uint32_t* bits, const uint64_t* key, std::size_t n,
                  const uint32_t* pairs, std::size_t n_pairs, float* out, std::size_t stride) {
    for (std::size_t s = 0; s < n; s += 8) {
        const __m512i idx = _mm512_loadu_si512(index + s);
        const __m512i nbits = _mm512_maskz_cvtepu32_epi64(
            __mmask8(0xff), _mm256_loadu_si256(reinterpret_cast<const __m256i*>(bits + s)));
        const uint32_t max_bits = *std::max_element(bits + s, bits + s + 8);
        const bool one_parity = std::all_of(
            bits + s, bits + s + 8, [&](uint32_t b) { return (b & 1u) == (max_bits & 1u); });
        const __m512i k = _mm512_loadu_si512(key + s);
        for (std::size_t p = 0; p < n_pairs; ++p) {
            // pair_key: the sample's key plus the pair's salt, hashed.
            const __m512i pk = mix(_mm512_add_epi64(k, set64(0x2505u * (uint64_t(pairs[p]) + 1))));
            const __m512i j = permute_lanes(idx, nbits, pk, max_bits, one_parity ? 2 : 1);
            // The bits above 32 key the scramble (scrambled() in zsobol_net.cpp).
            const __m512i hi = shr64(j, 32);
            const __m512i key2 = _mm512_mask_blend_epi64(_mm512_test_epi64_mask(hi, hi), pk,
                                                         mix(_mm512_xor_si512(pk, hi)));
            const __m256i j32 = low32(j);
            const __m256i x = owen_reversed(j32, _mm512_add_epi64(key2, set64(1)));
            const __m256i y =
                owen_reversed(bit_reverse(dim1_lanes(j32)), _mm512_add_epi64(key2, set64(2)));
            _mm256_storeu_ps(out + 2 * p * stride + s, unit_float(x));
            _mm256_storeu_ps(out + (2 * p + 1) * stride + s, unit_float(y));
        }
    }
}
#else
void sample_table(const uint64_t* index, const uint32_t* bits, const uint64_t* key, std::size_t n,
                  const uint32_t* pairs, std::size_t n_pairs, float* out, std::size_t stride) {
    sample_table_scalar(index, bits, key, (n + 7) / 8 * 8, pairs, n_pairs, out, stride);
}
#endif

}  // namespace foton::kern::zsobol
