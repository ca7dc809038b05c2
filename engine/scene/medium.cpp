#include "medium.h"

namespace foton {

MediumPoint Medium::at(const Vec3& p) const {
    MediumPoint c;
    if (kind == MediumKind::RGBGrid) {
        // A coefficient without a grid is 1 throughout the box (pbrt-v4's) and 0 outside.
        const Bounds3& b = density->box();
        if (!(p.x >= b.lo.x && p.y >= b.lo.y && p.z >= b.lo.z && p.x <= b.hi.x && p.y <= b.hi.y &&
              p.z <= b.hi.z))
            return MediumPoint{RGB{0.f}, RGB{0.f}, RGB{0.f}};
        c.sigma_a = (rgb_sigma_a ? rgb_sigma_a->lookup(p) : RGB{1.f}) * grid_scale;
        c.sigma_s = (rgb_sigma_s ? rgb_sigma_s->lookup(p) : RGB{1.f}) * grid_scale;
        c.Le = rgb_Le ? rgb_Le->lookup(p) * le_factor : RGB{0.f};
        return c;
    }
    const float rho = density->lookup(p);
    c.sigma_a = sigma_a * rho;
    c.sigma_s = sigma_s * rho;
    if (temperature) {
        const float kelvin = (temperature->lookup(p) - temperature_offset) * temperature_scale;
        c.Le = blackbody->at(kelvin) * (le_factor * (le_scale ? le_scale->lookup(p) : 1.f));
    } else {
        c.Le = le_scale ? Le * le_scale->lookup(p) : Le;
    }
    return c;
}

}  // namespace foton
