#pragma once
// Specular optics: mirror reflection, Snell refraction and the Fresnel reflectance of a
// dielectric interface (unpolarised light).
#include <cmath>

#include "kernels/fresnel.h"
#include "math.h"

namespace foton {

// The Fresnel terms (fresnel_dielectric, fresnel_conductor) live with the specular shading
// kernel that computes them too (kernels/fresnel.h).
using kern::fresnel_conductor;
using kern::fresnel_dielectric;

// Refracts unit direction d at a surface with unit normal n facing the incident side
// (dot(d, n) < 0); eta = eta_i / eta_t. Returns false under total internal reflection.
inline bool refract(const Vec3& d, const Vec3& n, float eta, Vec3& t) {
    const float cos_i = -dot(d, n);
    const float k = 1.f - eta * eta * (1.f - cos_i * cos_i);
    if (k < 0.f) return false;
    t = normalize(d * eta + n * (eta * cos_i - std::sqrt(k)));
    return true;
}

}  // namespace foton
