#pragma once
// Control variates for direct light (the photon-mapping thesis' 3.2.4): I = J + integral of
// (f - g), where g approximates the integrand f and J, the integral of g, is known in closed
// form. For a light sample at a Lambertian point, f is the light's contribution with
// visibility V and g the same without it, whose integral over a polygonal emitter of uniform
// radiance is Lambert's formula for the irradiance from a polygon. The primary estimate
// (3.22) is then
//
//     J + (V - 1) g / p  =  J - g / p  +  V g / p:
//
// the usual light sample (V g / p, still traced as a shadow ray) plus an unconditional term
// J - g / p, which is added without a ray. Where the light is seen whole, every estimate is J
// exactly: no noise in lit regions; where it is hidden the estimate is as noisy as the plain
// one; in penumbrae its variance is (3.23), of the order of the plain one. The plain estimator
// is used where the closed form does not apply (non-Lambertian points, interpolated shading
// normals, sphere, environment and delta lights, meshes of more than kMaxPolygons triangles).
#include "engine/core/math.h"
#include "engine/core/rgb.h"
#include "engine/scene/light_set.h"
#include "engine/scene/scene.h"
#include "shading_point.h"

namespace foton {

// Lambert's formula: the integral of cos(up, w) over the directions w from x through the
// convex polygon `corners` (n <= 4, in order) after clipping it to the hemisphere around `up`:
// 1/2 sum_i theta_i (up . unit(u_i x u_(i+1))) for the clipped corners' unit directions u_i.
// pi for a polygon covering the whole hemisphere; 0 for one wholly below it.
float polygon_cosine_integral(const Vec3* corners, int n, const Vec3& x, const Vec3& up);

// The same over what emitter `light` shows x (its triangle `tri` when the light BVH picked
// one), counting only faces whose emitting side faces x. False when no closed form applies.
bool emitter_cosine_integral(const LightSet& lights, const Scene& scene, uint32_t light,
                             uint32_t tri, const Vec3& x, const Vec3& up, float& integral);

inline constexpr uint32_t kMaxPolygons = 64;

// The unconditional term J / pick - sample for a light sample of `pick` at `v` whose
// unshadowed value was `sample` (zero when the sample failed): J / pick - g / p. Zero when the
// closed form does not apply, so adding it is always unbiased.
RGB direct_control_term(const LightSet& lights, const Scene& scene, const ShadingPoint& v,
                        const LightPick& pick, const RGB& sample);

}  // namespace foton
