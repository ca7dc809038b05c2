// compress_lanes: AVX-512 compress stores, 16 lanes a step; the scalar twin elsewhere.
#include "lane_compress.h"

#include <immintrin.h>

#include <cstring>

namespace foton::kern {

std::size_t compress_lanes_scalar(const float* valid, std::size_t n, const uint32_t* const* src,
                                  uint32_t* const* dst, std::size_t columns) {
    std::size_t out = 0;
    for (std::size_t k = 0; k < n; ++k) {
        if (valid[k] == 0.f) continue;
        // memcpy: the words may be floats' storage.
        for (std::size_t c = 0; c < columns; ++c) std::memcpy(dst[c] + out, src[c] + k, 4);
        ++out;
    }
    return out;
}

#if defined(__AVX512F__)
std::size_t compress_lanes(const float* valid, std::size_t n, const uint32_t* const* src,
                           uint32_t* const* dst, std::size_t columns) {
    std::size_t out = 0, k = 0;
    const __m512 zero = _mm512_setzero_ps();
    for (; k < n; k += 16) {
        // The last step's lanes past n take no part.
        const __mmask16 in = n - k >= 16 ? __mmask16(0xffff) : __mmask16((1u << (n - k)) - 1u);
        const __mmask16 m =
            _mm512_mask_cmp_ps_mask(in, _mm512_maskz_loadu_ps(in, valid + k), zero, _CMP_NEQ_UQ);
        if (m == 0) continue;
        for (std::size_t c = 0; c < columns; ++c)
            _mm512_mask_compressstoreu_epi32(dst[c] + out, m,
                                             _mm512_maskz_loadu_epi32(in, src[c] + k));
        out += std::size_t(__builtin_popcount(m));
    }
    return out;
}
#else
std::size_t compress_lanes(const float* valid, std::size_t n, const uint32_t* const* src,
                           uint32_t* const* dst, std::size_t columns) {
    return compress_lanes_scalar(valid, n, src, dst, columns);
}
#endif

}  // namespace foton::kern
