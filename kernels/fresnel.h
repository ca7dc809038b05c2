#pragma once
// Fresnel reflectance of dielectric and conductor interfaces (unpolarised light): the
// engine's optics (engine/core/optics.h) and the specular shading kernel's scalar twin
// (specular_shade_scalar.cpp) call these; the SIMD kernel does the same operations in order.
#include <algorithm>
#include <cmath>

namespace foton::kern {

// Fresnel reflectance for light crossing from a medium of index eta_i into eta_t, with
// cos_i the cosine between the incident direction (reversed) and the normal on the incident
// side. Returns 1 under total internal reflection.
inline float fresnel_dielectric(float cos_i, float eta_i, float eta_t) {
    cos_i = std::clamp(cos_i, 0.f, 1.f);
    const float sin_i = std::sqrt(std::max(0.f, 1.f - cos_i * cos_i));
    const float sin_t = eta_i / eta_t * sin_i;
    if (sin_t >= 1.f) return 1.f;
    const float cos_t = std::sqrt(std::max(0.f, 1.f - sin_t * sin_t));
    const float r_par = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
    const float r_perp = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
    return 0.5f * (r_par * r_par + r_perp * r_perp);
}

// Fresnel reflectance of a conductor with complex index eta + i k (relative to the medium
// the light comes from), unpolarised, exact: the thesis' (A.4)/(A.5) are the approximation
// of this for eta^2 + k^2 >> 1. With k = 0 it equals fresnel_dielectric(cos_i, 1, eta).
inline float fresnel_conductor(float cos_i, float eta, float k) {
    cos_i = std::clamp(cos_i, 0.f, 1.f);
    const float cos2 = cos_i * cos_i, sin2 = 1.f - cos2;
    const float eta2 = eta * eta, k2 = k * k;
    const float t0 = eta2 - k2 - sin2;
    const float a2b2 = std::sqrt(std::max(0.f, t0 * t0 + 4.f * eta2 * k2));
    const float a = std::sqrt(std::max(0.f, 0.5f * (a2b2 + t0)));
    const float t1 = a2b2 + cos2, t2 = 2.f * cos_i * a;
    const float rs = (t1 - t2) / (t1 + t2);
    const float t3 = cos2 * a2b2 + sin2 * sin2, t4 = t2 * sin2;
    const float rp = rs * (t3 - t4) / (t3 + t4);
    return 0.5f * (rs + rp);
}

}  // namespace foton::kern
