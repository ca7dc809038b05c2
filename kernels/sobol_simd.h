#pragma once
// The AVX-512 pieces the Sobol' and Z-Sobol' table kernels share (sobol_table.cpp,
// zsobol_table.cpp), besides the 64-bit hash of hash_simd.h: bit reversal, the second
// dimension's table lookups and the Owen scramble in 32-bit lanes. FOTON_SOBOL_SIMD says
// whether the build has the extensions they need (F, DQ, CD, VL); without them the kernels run
// their scalar twins.
#include <immintrin.h>

#include <cstdint>

#include "hash_simd.h"
#include "sobol_net.h"

#if defined(__AVX512F__) && defined(__AVX512DQ__) && defined(__AVX512CD__) && defined(__AVX512VL__)
#define FOTON_SOBOL_SIMD 1

namespace foton::kern::sobol_simd {

using namespace hash_simd;

inline __m256i bit_reverse(__m256i i) {
    auto swap = [](__m256i x, int s, uint32_t m) {
        const __m256i mask = _mm256_set1_epi32(int32_t(m));
        return _mm256_or_si256(_mm256_slli_epi32(_mm256_and_si256(x, mask), s),
                               _mm256_and_si256(_mm256_srli_epi32(x, s), mask));
    };
    i = _mm256_or_si256(_mm256_slli_epi32(i, 16), _mm256_srli_epi32(i, 16));
    i = swap(i, 8, 0x00ff00ffu);
    i = swap(i, 4, 0x0f0f0f0fu);
    i = swap(i, 2, 0x33333333u);
    return swap(i, 1, 0x55555555u);
}

inline __m256i dim1_lanes(__m256i i) {
    const int* t = reinterpret_cast<const int*>(sobol::dim1_tables());
    const __m256i byte = _mm256_set1_epi32(0xff);
    __m256i out = _mm256_setzero_si256();
    for (int b = 0; b < 4; ++b) {
        const __m256i idx = _mm256_add_epi32(_mm256_and_si256(_mm256_srli_epi32(i, 8 * b), byte),
                                             _mm256_set1_epi32(256 * b));
        out = _mm256_xor_si256(
            out, _mm256_mmask_i32gather_epi32(_mm256_setzero_si256(), __mmask8(0xff), idx, t, 4));
    }
    return out;
}

// owen_scramble(v, seed) where x = v bit-reversed is given.
inline __m256i owen_reversed(__m256i x, __m512i seed) {
    const __m512i h = mix(seed);
    const __m512i h2 = mix(_mm512_xor_si512(seed, _mm512_set1_epi64(0x632be59bd9b4e019ll)));
    x = _mm256_add_epi32(x, low32(h));
    x = _mm256_mullo_epi32(x, _mm256_or_si256(low32(shr64(h, 32)), _mm256_set1_epi32(1)));
    x = _mm256_xor_si256(x, _mm256_mullo_epi32(x, _mm256_slli_epi32(low32(h2), 1)));
    x = _mm256_add_epi32(x, low32(shr64(h2, 32)));
    x = _mm256_xor_si256(x, _mm256_mullo_epi32(x, _mm256_set1_epi32(0x7a6b5c4e)));
    return bit_reverse(x);
}

inline __m256 unit_float(__m256i v) {
    return _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_srli_epi32(v, 8)),
                         _mm256_set1_ps(1.f / 16777216.f));
}

}  // namespace foton::kern::sobol_simd

#else
#define FOTON_SOBOL_SIMD 0
#endif
