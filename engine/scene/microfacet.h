#pragma once
// Microfacet normal distributions of the photon-mapping thesis (appendix A): Blinn's
// cos^e, Beckmann's Gaussian slopes, and Ashikhmin–Shirley's anisotropic cos^(e(phi)).
// Every D is normalised so that the projected microfacet area is the macro surface,
// integral of D(h) cos(theta_h) over the hemisphere = 1, and is sampled exactly by that
// density (pdf_h = D(h) cos(theta_h)). Directions are local: z is the surface normal and x
// the tangent that the anisotropic exponent nu runs along.
#include <cmath>

#include "engine/core/math.h"
#include "engine/core/sampler.h"

namespace foton {

enum class MicrofacetKind { Blinn, Beckmann, AshikhminShirley };
const char* microfacet_name(MicrofacetKind k);

struct MicrofacetDistribution {
    MicrofacetKind kind = MicrofacetKind::Beckmann;
    float alpha = 0.2f;  // Beckmann RMS slope
    float nu = 100.f;    // Blinn exponent (nu = nv) or Ashikhmin–Shirley's exponent along x
    float nv = 100.f;    // Ashikhmin–Shirley's exponent along y

    static MicrofacetDistribution blinn(float exponent);
    static MicrofacetDistribution beckmann(float alpha);
    static MicrofacetDistribution ashikhmin_shirley(float nu, float nv);

    float D(const Vec3& h) const;
    // A microfacet normal distributed as D(h) cos(theta_h).
    Vec3 sample_h(Point2 u) const;
    float pdf_h(const Vec3& h) const { return D(h) * std::fabs(h.z); }
};

// The V-cavity shadowing/masking term of Torrance–Sparrow and Cook–Torrance.
inline float vcavity_g(const Vec3& wo, const Vec3& wi, const Vec3& h) {
    const float oh = std::fabs(dot(wo, h));
    if (oh == 0.f) return 0.f;
    const float k = 2.f * std::fabs(h.z) / oh;
    return std::min({1.f, k * std::fabs(wo.z), k * std::fabs(wi.z)});
}

}  // namespace foton
