#pragma once
// log2, exp2 and what is built on them (pow of a positive base, exp) for the glossy lobes of
// the shading kernels: Cephes' log2f and exp2f polynomials (about 2 ulp), written once for
// float and for SIMD batches, so that a kernel and its scalar twin do the very same operations
// and agree bit for bit (libm's powf and expf differ between the two). The split of a float
// into exponent and mantissa and the join of 2^n are exact integer operations, done by
// std::bit_cast here and by bitwise casts in shade_lanes.h's vector versions.
#include <bit>
#include <cmath>
#include <cstdint>

namespace foton::kern {

// log2(1 + x) + e for the mantissa's x in [sqrt(1/2) - 1, sqrt(2) - 1) (Cephes log2f).
template <class T>
inline T log2_reduced(const T& x, const T& e) {
    const T z = x * x;
    T y = (((((((T(7.0376836292e-2f) * x + T(-1.1514610310e-1f)) * x + T(1.1676998740e-1f)) * x +
               T(-1.2420140846e-1f)) *
                  x +
              T(1.4249322787e-1f)) *
                 x +
             T(-1.6668057665e-1f)) *
                x +
            T(2.0000714765e-1f)) *
               x +
           T(-2.4999993993e-1f)) *
              x +
          T(3.3333331174e-1f);
    y = y * x * z - T(0.5f) * z;
    // log2(e) - 1, so that x + x (log2(e) - 1) keeps x's bits exact.
    const T log2ea(0.44269504088896340736f);
    return (((y * log2ea + x * log2ea) + y) + x) + e;
}

// 2^f for f in [-0.5, 0.5] (Cephes exp2f).
template <class T>
inline T exp2_reduced(const T& f) {
    const T p = (((((T(1.535336188319500e-4f) * f + T(1.339887440266574e-3f)) * f +
                    T(9.618437357674640e-3f)) *
                       f +
                   T(5.550332471162809e-2f)) *
                      f +
                  T(2.402264791363012e-1f)) *
                     f +
                 T(6.931472028550421e-1f)) *
                f;
    return T(1.f) + p;
}

inline constexpr float kSqrtHalf = 0.70710678118654752440f;
inline constexpr float kLog2e = 1.44269504088896340736f;
inline constexpr float kLn2 = 0.69314718055994530942f;
// exp2 of less is 0 (no subnormal results), of more is clamped (never reached here).
inline constexpr float kExp2Min = -126.f, kExp2Max = 127.f;

// log2(x) for x > 0; below the smallest normal float x counts as that float.
inline float log2_poly(float x) {
    x = x < 0x1p-126f ? 0x1p-126f : x;
    const uint32_t bits = std::bit_cast<uint32_t>(x);
    // x = m 2^e with m in [0.5, 1), then m in [sqrt(1/2), sqrt(2)).
    float e = float(int32_t(bits & 0x7f800000u)) * 0x1p-23f - 126.f;
    const float m = std::bit_cast<float>((bits & 0x007fffffu) | 0x3f000000u);
    const bool low = m < kSqrtHalf;
    e = low ? e - 1.f : e;
    const float r = low ? (m + m) - 1.f : m - 1.f;
    return log2_reduced(r, e);
}

// 2^x: 0 below kExp2Min.
inline float exp2_poly(float x) {
    if (!(x >= kExp2Min)) return 0.f;
    x = x > kExp2Max ? kExp2Max : x;
    const float n = std::floor(x + 0.5f);
    const float p = exp2_reduced(x - n);
    // 2^n from its biased exponent, (n + 127) 2^23 as the float's bits.
    const float scale = std::bit_cast<float>(int32_t((n + 127.f) * 0x1p23f));
    return p * scale;
}

// x^y for x >= 0, y > 0 (0 at x = 0).
inline float pow_poly(float x, float y) {
    return x > 0.f ? exp2_poly(y * log2_poly(x)) : 0.f;
}

// e^x.
inline float exp_poly(float x) {
    return exp2_poly(x * kLog2e);
}

// ln(x) for x > 0.
inline float log_poly(float x) {
    return log2_poly(x) * kLn2;
}

}  // namespace foton::kern
