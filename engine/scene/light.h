#pragma once
// Light sources of the Whitted renderer. Point and spot lights follow the thesis'
// attenuation I / (1 + a d^2) (a = 0: no fall-off); the rectangle area light is given in
// radiance and sampled with several shadow rays.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "engine/core/math.h"
#include "engine/core/rgb.h"
#include "engine/core/sampler.h"

namespace foton {

// The most a light's intensity or radiance, a material's emission or an environment map's
// texel times its scale may be: the sums of many samples of it, times geometry and BSDF
// factors, must stay finite in float (1e38 gave NaN pixels). The loaders refuse more at the
// value's line.
inline constexpr float kMaxEmission = 1e15f;
// "" when every component of v is finite, not negative and at most kMaxEmission; else what
// is wrong with it.
inline std::string emission_problem(const RGB& v) {
    const float c[3] = {v.r, v.g, v.b};
    for (const float x : c) {
        if (!std::isfinite(x)) return "is NaN or infinite";
        if (x < 0.f) return "is negative";
        if (x > kMaxEmission) {
            char buf[96];
            std::snprintf(buf, sizeof buf, "is %g, above foton's limit of %g", double(x),
                          double(kMaxEmission));
            return buf;
        }
    }
    return "";
}

struct PointLight {
    Vec3 position;
    RGB intensity;  // colour * intensity
    float attenuation = 0.f;
};

struct DirectionalLight {
    Vec3 direction;  // unit, the direction light travels
    RGB radiance;    // colour * intensity; irradiance on a facing surface
};

struct SpotLight {
    Vec3 position;
    Vec3 direction;  // unit, the cone axis
    RGB intensity;
    float attenuation = 0.f;
    float cos_outer = 0.f;  // no light outside the cone
    float cos_inner = 0.f;  // full intensity inside; smooth fall-off in between
    float falloff(float cos_theta) const;
};

// A one-sided rectangle: corner + two edges, emitting on the side of cross(edge1, edge2).
struct AreaLight {
    Vec3 corner, edge1, edge2;
    Vec3 normal;  // unit
    float area = 0.f;
    RGB radiance;
    uint32_t samples = 1;
    SamplerKind sampler = SamplerKind::Jittered;
    uint32_t geometry = 0xffffffffu;  // the scene object that makes it visible
};

struct Ambient {
    RGB color{1.f};
    float intensity = 0.f;
    RGB radiance() const { return color * intensity; }
};

struct Lights {
    std::vector<PointLight> points;
    std::vector<DirectionalLight> directionals;
    std::vector<SpotLight> spots;
    std::vector<AreaLight> areas;
    std::size_t count() const {
        return points.size() + directionals.size() + spots.size() + areas.size();
    }
};

inline float SpotLight::falloff(float cos_theta) const {
    if (cos_theta <= cos_outer) return 0.f;
    if (cos_theta >= cos_inner) return 1.f;
    const float x = (cos_theta - cos_outer) / (cos_inner - cos_outer);
    return x * x * (3.f - 2.f * x);  // smoothstep
}

}  // namespace foton
