#pragma once
// Light sources of the Whitted renderer. Point and spot lights follow the thesis'
// attenuation I / (1 + a d^2) (a = 0: no fall-off); the rectangle area light is given in
// radiance and sampled with several shadow rays.
#include <cstdint>
#include <vector>

#include "engine/core/math.h"
#include "engine/core/rgb.h"
#include "engine/core/sampler.h"

namespace foton {

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
