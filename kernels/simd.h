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

// Bit i set when lane i of the mask is true (any width: 4, 8 or 16 lanes).
template <class A>
inline uint32_t movemask(const xsimd::batch_bool<float, A>& m) {
    return detail::mask_bits(static_cast<typename xsimd::batch_bool<float, A>::register_type>(m));
}

// The architecture of a given lane count, for kernels whose natural width differs from the
// widest one (a BVH node of 8 children, a leaf block of 4 triangles) on the same machine.
template <std::size_t W>
struct ArchOfWidth;
template <>
struct ArchOfWidth<4> {
#if defined(__SSE4_2__)
    using type = xsimd::sse4_2;
#else
    using type = xsimd::sse2;
#endif
};
#if defined(__AVX__)
template <>
struct ArchOfWidth<8> {
#if defined(__AVX2__)
    using type = xsimd::avx2;
#else
    using type = xsimd::avx;
#endif
};
#endif
#if defined(__AVX512BW__)
template <>
struct ArchOfWidth<16> {
    using type = xsimd::avx512bw;
};
#endif
template <std::size_t W>
using FloatW = xsimd::batch<float, typename ArchOfWidth<W>::type>;
// The widest of 8 and 4 lanes this build has (BVH nodes, see kernels/bvh_node.h).
#if defined(__AVX__)
inline constexpr std::size_t kHalfWidth = 8;
#else
inline constexpr std::size_t kHalfWidth = 4;
#endif

// Lane-wise minimum / maximum: the x86 min/max instructions, which are exactly
// select(a < b, a, b) and select(a > b, a, b): a NaN in either operand, or equal operands, yield
// `b`. The kernels rely on that asymmetry (a NaN slab drops out of a box test when the non-NaN
// value is `b`). Not xsimd::min/max: GCC 12 warns (-Wmaybe-uninitialized) inside its own AVX-512
// forms of those, and a select compiles to a compare and a blend, twice the instructions.
namespace detail {
#if defined(__AVX512F__)
// The masked forms: GCC 12's plain _mm512_min_ps passes an undefined source it then warns about.
inline __m512 min_reg(__m512 a, __m512 b) {
    return _mm512_mask_min_ps(b, __mmask16(0xffff), a, b);
}
inline __m512 max_reg(__m512 a, __m512 b) {
    return _mm512_mask_max_ps(b, __mmask16(0xffff), a, b);
}
#endif
#if defined(__AVX__)
inline __m256 min_reg(__m256 a, __m256 b) {
    return _mm256_min_ps(a, b);
}
inline __m256 max_reg(__m256 a, __m256 b) {
    return _mm256_max_ps(a, b);
}
#endif
inline __m128 min_reg(__m128 a, __m128 b) {
    return _mm_min_ps(a, b);
}
inline __m128 max_reg(__m128 a, __m128 b) {
    return _mm_max_ps(a, b);
}
#if defined(__AVX512F__)
inline __m512 sqrt_reg(__m512 a) {
    return _mm512_mask_sqrt_ps(a, __mmask16(0xffff), a);
}
#endif
#if defined(__AVX__)
inline __m256 sqrt_reg(__m256 a) {
    return _mm256_sqrt_ps(a);
}
#endif
inline __m128 sqrt_reg(__m128 a) {
    return _mm_sqrt_ps(a);
}
}  // namespace detail

template <class A>
inline xsimd::batch<float, A> vmin(const xsimd::batch<float, A>& a,
                                   const xsimd::batch<float, A>& b) {
    using R = typename xsimd::batch<float, A>::register_type;
    return xsimd::batch<float, A>(detail::min_reg(static_cast<R>(a), static_cast<R>(b)));
}
template <class A>
inline xsimd::batch<float, A> vmax(const xsimd::batch<float, A>& a,
                                   const xsimd::batch<float, A>& b) {
    using R = typename xsimd::batch<float, A>::register_type;
    return xsimd::batch<float, A>(detail::max_reg(static_cast<R>(a), static_cast<R>(b)));
}

// Lane-wise square root, correctly rounded like std::sqrt (not xsimd::sqrt, whose AVX-512 form
// draws the same GCC 12 warning as min/max above).
template <class A>
inline xsimd::batch<float, A> vsqrt(const xsimd::batch<float, A>& a) {
    using R = typename xsimd::batch<float, A>::register_type;
    return xsimd::batch<float, A>(detail::sqrt_reg(static_cast<R>(a)));
}

// Lane-wise truncation to int32 (xsimd::to_int's AVX-512 form draws the same GCC 12 warning).
template <class A>
inline xsimd::batch<int32_t, A> to_int(const xsimd::batch<float, A>& a) {
#if defined(__AVX512F__)
    if constexpr (xsimd::batch<float, A>::size == 16)
        return xsimd::batch<int32_t, A>(
            _mm512_maskz_cvttps_epi32(__mmask16(0xffff), static_cast<__m512>(a)));
    else
#endif
        return xsimd::to_int(a);
}

// Lane-wise floor (xsimd::floor's AVX-512 form draws the same GCC 12 warning).
template <class A>
inline xsimd::batch<float, A> vfloor(const xsimd::batch<float, A>& a) {
#if defined(__AVX512F__)
    if constexpr (xsimd::batch<float, A>::size == 16)
        return xsimd::batch<float, A>(_mm512_mask_roundscale_ps(
            static_cast<__m512>(a), __mmask16(0xffff), static_cast<__m512>(a),
            _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC));
    else
#endif
        return xsimd::floor(a);
}

// Lane-wise int32 to float (xsimd::to_float's AVX-512 form draws the same GCC 12 warning).
template <class A>
inline xsimd::batch<float, A> to_float(const xsimd::batch<int32_t, A>& a) {
#if defined(__AVX512F__)
    if constexpr (xsimd::batch<float, A>::size == 16)
        return xsimd::batch<float, A>(
            _mm512_maskz_cvtepi32_ps(__mmask16(0xffff), static_cast<__m512i>(a)));
    else
#endif
        return xsimd::to_float(a);
}

// Lane-wise gather of base[index] (xsimd 8.1 gathers element by element on AVX-512).
template <class A>
inline xsimd::batch<float, A> gather(const float* base, const xsimd::batch<int32_t, A>& index) {
#if defined(__AVX512F__)
    if constexpr (xsimd::batch<float, A>::size == 16)
        return xsimd::batch<float, A>(_mm512_mask_i32gather_ps(
            _mm512_setzero_ps(), __mmask16(0xffff), static_cast<__m512i>(index), base, 4));
    else
#endif
#if defined(__AVX2__)
        if constexpr (xsimd::batch<float, A>::size == 8)
        return xsimd::batch<float, A>(_mm256_i32gather_ps(base, static_cast<__m256i>(index), 4));
    else
#endif
        return xsimd::batch<float, A>::gather(base, index);
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
