// pbrt-v4's thin dielectric: a slab so thin that light leaving it lands where it entered.
// Every path inside the slab is summed in closed form: with the interface's Fresnel
// reflectance R0 and T0 = 1 - R0, the slab reflects R0 + T0^2 R0 (1 + R0^2 + R0^4 + ...) =
// R0 + T0^2 R0 / (1 - R0^2) and transmits the rest, undeviated (the two refractions cancel).
// Both are delta lobes; no radiance scaling, since the light ends in the medium it came from.
#include <cmath>

#include "bsdf.h"
#include "engine/core/optics.h"

namespace foton {

float thin_dielectric_reflectance(float cos_theta, float ior) {
    const float r0 = fresnel_dielectric(std::fabs(cos_theta), 1.f, ior);
    if (r0 >= 1.f) return 1.f;
    const float t0 = 1.f - r0;
    return r0 + t0 * t0 * r0 / (1.f - r0 * r0);
}

bool thin_dielectric_sample(const Lobe& l, const Vec3& wo, float uc, BsdfSample& s) {
    const float cos_o = std::fabs(wo.z);
    if (cos_o == 0.f) return false;
    const float r = thin_dielectric_reflectance(cos_o, l.fresnel.ior);
    s.eta = 1.f;
    if (uc < r) {
        s.wi = {-wo.x, -wo.y, wo.z};
        s.f = l.color * (r / cos_o);
        s.pdf = r;
        s.flags = kSpecular | kReflection;
        return r > 0.f;
    }
    s.wi = -wo;
    s.f = l.transmit * ((1.f - r) / cos_o);
    s.pdf = 1.f - r;
    s.flags = kSpecular | kTransmission;
    return true;
}

}  // namespace foton
