// uniform_table: AVX-512 (with its DQ extension's 64-bit multiply) draws 8 numbers of one
// dimension at once; other builds run the scalar twin.
#include "counter_hash.h"

#include "hash_simd.h"

namespace foton::kern {

void uniform_table_scalar(uint64_t prefix, const uint64_t* index, std::size_t n,
                          const uint64_t* dims, std::size_t n_dims, float* out,
                          std::size_t stride) {
    for (std::size_t d = 0; d < n_dims; ++d)
        for (std::size_t i = 0; i < n; ++i)
            out[d * stride + i] = to_unit_float(hash_from(prefix, index[i], dims[d]));
}

#if FOTON_HASH_SIMD
using namespace hash_simd;

void uniform_table(uint64_t prefix, const uint64_t* index, std::size_t n, const uint64_t* dims,
                   std::size_t n_dims, float* out, std::size_t stride) {
    const __m512i pre = _mm512_set1_epi64(int64_t(prefix));
    const __m256 scale = _mm256_set1_ps(1.f / 16777216.f);
    // Dimension by dimension over all indices, two registers at a time: two independent
    // multiply chains keep the multiplier busy.
    for (std::size_t d = 0; d < n_dims; ++d) {
        const __m512i step = _mm512_set1_epi64(int64_t(0x85157af5ull * (dims[d] + 1)));
        const __m512i dim = _mm512_set1_epi64(int64_t(dims[d]));
        auto draw = [&](std::size_t i) {
            const __m512i k = _mm512_loadu_si512(index + i);
            const __m512i h =
                mix(_mm512_xor_si512(mix(_mm512_xor_si512(pre, _mm512_add_epi64(k, step))), dim));
            return _mm256_mul_ps(_mm512_maskz_cvtepu64_ps(__mmask8(0xff), shr64(h, 40)), scale);
        };
        std::size_t i = 0;
        for (; i + 16 <= n; i += 16) {
            const __m256 a = draw(i), b = draw(i + 8);
            _mm256_storeu_ps(out + d * stride + i, a);
            _mm256_storeu_ps(out + d * stride + i + 8, b);
        }
        for (; i < n; i += 8) _mm256_storeu_ps(out + d * stride + i, draw(i));
    }
}
#else
void uniform_table(uint64_t prefix, const uint64_t* index, std::size_t n, const uint64_t* dims,
                   std::size_t n_dims, float* out, std::size_t stride) {
    uniform_table_scalar(prefix, index, (n + 7) / 8 * 8, dims, n_dims, out, stride);
}
#endif

}  // namespace foton::kern
