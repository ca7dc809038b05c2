#pragma once
// Microfacet normal distributions of the photon-mapping thesis (appendix A): Blinn's
// cos^e, Beckmann's Gaussian slopes, and Ashikhmin–Shirley's anisotropic cos^(e(phi)); and the
// field's Trowbridge–Reitz (GGX) of anisotropic roughness alpha_x, alpha_y (pbrt-v4's
// conductor, dielectric and coated materials, glTF's metallic-roughness).
// Every D is normalised so that the projected microfacet area is the macro surface,
// integral of D(h) cos(theta_h) over the hemisphere = 1. The thesis' models are sampled
// exactly by that density (pdf_h = D(h) cos(theta_h)) and shadowed by the V-cavity term;
// Trowbridge–Reitz by the normals visible from wo (Heitz 2018), pdf G1(wo) D(h) (wo.h) / wo.z,
// and shadowed by Smith's height-correlated term. Directions are local: z is the surface
// normal and x the tangent that nu (alpha_x) runs along.
#include <cmath>

#include "engine/core/math.h"
#include "engine/core/sampler.h"

namespace foton {

enum class MicrofacetKind { Blinn, Beckmann, AshikhminShirley, TrowbridgeReitz };
const char* microfacet_name(MicrofacetKind k);

struct MicrofacetDistribution {
    MicrofacetKind kind = MicrofacetKind::Beckmann;
    float alpha = 0.2f;    // Beckmann RMS slope; Trowbridge–Reitz alpha along x
    float alpha_y = 0.2f;  // Trowbridge–Reitz alpha along y
    float nu = 100.f;      // Blinn exponent (nu = nv) or Ashikhmin–Shirley's exponent along x
    float nv = 100.f;      // Ashikhmin–Shirley's exponent along y

    static MicrofacetDistribution blinn(float exponent);
    static MicrofacetDistribution beckmann(float alpha);
    static MicrofacetDistribution ashikhmin_shirley(float nu, float nv);
    static MicrofacetDistribution trowbridge_reitz(float alpha_x, float alpha_y);

    bool visible_normals() const { return kind == MicrofacetKind::TrowbridgeReitz; }
    float D(const Vec3& h) const;
    // A microfacet normal distributed as D(h) cos(theta_h) (the thesis' models).
    Vec3 sample_h(Point2 u) const;
    float pdf_h(const Vec3& h) const { return D(h) * std::fabs(h.z); }

    // Trowbridge–Reitz: Smith's Lambda, the masking G1 = 1 / (1 + Lambda) and the
    // height-correlated shadowing-masking G = 1 / (1 + Lambda(wo) + Lambda(wi)).
    float lambda(const Vec3& w) const;
    float g1(const Vec3& w) const { return 1.f / (1.f + lambda(w)); }
    float smith_g(const Vec3& wo, const Vec3& wi) const {
        return 1.f / (1.f + lambda(wo) + lambda(wi));
    }
    // A normal visible from wo (wo.z > 0), distributed as G1(wo) D(h) max(0, wo.h) / wo.z.
    Vec3 sample_visible(const Vec3& wo, Point2 u) const;
};

// The V-cavity shadowing/masking term of Torrance–Sparrow and Cook–Torrance.
inline float vcavity_g(const Vec3& wo, const Vec3& wi, const Vec3& h) {
    const float oh = std::fabs(dot(wo, h));
    if (oh == 0.f) return 0.f;
    const float k = 2.f * std::fabs(h.z) / oh;
    return std::min({1.f, k * std::fabs(wo.z), k * std::fabs(wi.z)});
}

}  // namespace foton
