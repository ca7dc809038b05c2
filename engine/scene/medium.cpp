#include "medium.h"

namespace foton {

namespace {
// An rgbgrid's coefficients without a grid are 1 throughout its box (pbrt-v4's) and 0 outside.
bool inside(const Bounds3& b, const Vec3& p) {
    return p.x >= b.lo.x && p.y >= b.lo.y && p.z >= b.lo.z && p.x <= b.hi.x && p.y <= b.hi.y &&
           p.z <= b.hi.z;
}
}  // namespace

MediumPoint Medium::at(const Vec3& p) const {
    if (kind == MediumKind::RGBGrid) {
        if (!inside(density->box(), p)) return {RGB{0.f}, RGB{0.f}};
        return {(rgb_sigma_a ? rgb_sigma_a->lookup(p) : RGB{1.f}) * grid_scale,
                (rgb_sigma_s ? rgb_sigma_s->lookup(p) : RGB{1.f}) * grid_scale};
    }
    const float rho = density->lookup(p);
    return {sigma_a * rho, sigma_s * rho};
}

RGB Medium::emission_at(const Vec3& p) const {
    if (kind == MediumKind::RGBGrid) return rgb_Le ? rgb_Le->lookup(p) * le_factor : RGB{0.f};
    if (temperature) {
        const float kelvin = (temperature->lookup(p) - temperature_offset) * temperature_scale;
        return blackbody->at(kelvin) * (le_factor * (le_scale ? le_scale->lookup(p) : 1.f));
    }
    return le_scale ? Le * le_scale->lookup(p) : Le;
}

}  // namespace foton
