#pragma once
// The one place that chooses the SIMD width. Kernels are written against FloatV so that SSE,
// AVX2 and AVX-512 builds come from one source; xsimd 8.1 lacks a batch_bool -> bitmask
// conversion, so movemask() below supplies it per ISA.
#include <cstddef>
#include <cstdint>

#include <immintrin.h>
#include <xsimd/xsimd.hpp>

namespace foton::simd {

using Arch = xsimd::default_arch;
using FloatV = xsimd::batch<float, Arch>;
using MaskV = FloatV::batch_bool_type;
inline constexpr std::size_t kWidth = FloatV::size;

namespace detail {
#if defined(__AVX512F__)
inline uint32_t mask_bits(__mmask16 r) {
    return r;
}
#endif
#if defined(__AVX__)
inline uint32_t mask_bits(__m256 r) {
    return static_cast<uint32_t>(_mm256_movemask_ps(r));
}
#endif
#if defined(__SSE__)
inline uint32_t mask_bits(__m128 r) {
    return static_cast<uint32_t>(_mm_movemask_ps(r));
}
#endif
}  // namespace detail

// Bit i set when lane i of the mask is true.
inline uint32_t movemask(const MaskV& m) {
    return detail::mask_bits(static_cast<typename MaskV::register_type>(m));
}

// Lane-wise minimum / maximum as selects: GCC 12 warns (-Wmaybe-uninitialized) inside its own
// AVX-512 min/max intrinsics, which xsimd::min/max use. Not NaN-symmetric: a NaN in `a`
// yields `b`.
inline FloatV vmin(const FloatV& a, const FloatV& b) {
    return xsimd::select(a < b, a, b);
}
inline FloatV vmax(const FloatV& a, const FloatV& b) {
    return xsimd::select(a > b, a, b);
}

// Horizontal minimum / maximum (xsimd 8.1 has neither).
inline float hmin(const FloatV& v) {
    alignas(64) float a[kWidth];
    v.store_aligned(a);
    float m = a[0];
    for (std::size_t i = 1; i < kWidth; ++i) m = a[i] < m ? a[i] : m;
    return m;
}
inline float hmax(const FloatV& v) {
    alignas(64) float a[kWidth];
    v.store_aligned(a);
    float m = a[0];
    for (std::size_t i = 1; i < kWidth; ++i) m = a[i] > m ? a[i] : m;
    return m;
}

}  // namespace foton::simd
