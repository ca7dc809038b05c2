#pragma once
// mix64 (counter_hash.h) eight 64-bit lanes at a time, with the shifts and narrowing it needs:
// what the number-table kernels share (counter_hash.cpp, sobol_table.cpp, zsobol_table.cpp).
// FOTON_HASH_SIMD says whether the build has AVX-512 F and DQ (the 64-bit multiply); the
// shifts and the narrowing are the masked forms, because GCC 12's plain ones pass an
// undefined source it then warns about.
#include <immintrin.h>

#include <cstdint>

#if defined(__AVX512F__) && defined(__AVX512DQ__)
#define FOTON_HASH_SIMD 1

namespace foton::kern::hash_simd {

inline __m512i shr64(__m512i z, unsigned n) {
    return _mm512_maskz_srli_epi64(__mmask8(0xff), z, n);
}
inline __m512i shl64(__m512i z, unsigned n) {
    return _mm512_maskz_slli_epi64(__mmask8(0xff), z, n);
}
inline __m512i mix(__m512i z) {
    z = _mm512_mullo_epi64(_mm512_xor_si512(z, shr64(z, 30)),
                           _mm512_set1_epi64(int64_t(0xbf58476d1ce4e5b9ull)));
    z = _mm512_mullo_epi64(_mm512_xor_si512(z, shr64(z, 27)),
                           _mm512_set1_epi64(int64_t(0x94d049bb133111ebull)));
    return _mm512_xor_si512(z, shr64(z, 31));
}
// The low 32 bits of each 64-bit lane.
inline __m256i low32(__m512i z) {
    return _mm512_maskz_cvtepi64_epi32(__mmask8(0xff), z);
}

}  // namespace foton::kern::hash_simd

#else
#define FOTON_HASH_SIMD 0
#endif
