#pragma once
// The constants shade_diffuse and its scalar twin share, equal to the engine's (core/math.h's
// pi, transport/common/mis.h's tie tolerance, offset_epsilon's relative offset): the kernels
// floor includes no engine header.
namespace foton::kern {

inline constexpr float kDiffusePi = 3.14159265358979323846f;
inline constexpr float kDiffuseInvPi = 1.f / kDiffusePi;
// The maximum heuristic declares a tie within this factor (mis.h's kMaxTieTolerance).
inline constexpr float kDiffuseMaxTie = 1.f + 1e-3f;
// Rays leave a surface pushed off by this times (largest |coordinate| + distance).
inline constexpr float kDiffuseOffset = 2e-5f;

// sin and cos of x in [-pi/4, pi/4] by Cephes' minimax polynomials (sinf/cosf, about 1 ulp
// there), for float and for SIMD batches alike: the kernel and its scalar twin do the very
// same operations, so their directions agree bit for bit. (The concentric disc needs no other
// range: its angles beyond pi/4 are pi/2 minus one within it.)
template <class T>
inline void sincos_quarter(const T& x, T& s, T& c) {
    const T z = x * x;
    s = ((T(-1.9515295891e-4f) * z + T(8.3321608736e-3f)) * z + T(-1.6666654611e-1f)) * z * x + x;
    c = ((T(2.443315711809948e-5f) * z + T(-1.388731625493765e-3f)) * z +
         T(4.166664568298827e-2f)) *
            z * z -
        T(0.5f) * z + T(1.f);
}

// sin and cos of 2 pi u for u in [0, 1): the turn split into quarters around k pi / 2
// (k = 0..4, counted by comparisons, so no conversion rounds differently in the kernel and
// its twin) and sincos_quarter of the rest, rotated into its quadrant.
inline void sincos_turn(float u, float& s, float& c) {
    const float x4 = u * 4.f;
    const float k =
        ((float(x4 >= 0.5f) + float(x4 >= 1.5f)) + float(x4 >= 2.5f)) + float(x4 >= 3.5f);
    float sr, cr;
    sincos_quarter((x4 - k) * 1.57079632679489661923f, sr, cr);
    const int quadrant = int(k) & 3;
    s = quadrant == 0 ? sr : quadrant == 1 ? cr : quadrant == 2 ? -sr : -cr;
    c = quadrant == 0 ? cr : quadrant == 1 ? -sr : quadrant == 2 ? -cr : sr;
}

}  // namespace foton::kern
