#include "subsurface.h"

#include <algorithm>

namespace foton {

void subsurface_from_reflectance(const BssrdfTable& table, const RGB& reflectance, const RGB& mfp,
                                 RGB& sigma_a, RGB& sigma_s) {
    const float r[3] = {reflectance.r, reflectance.g, reflectance.b}, l[3] = {mfp.r, mfp.g, mfp.b};
    float sa[3], ss[3];
    for (int c = 0; c < 3; ++c) {
        const float rho = table.albedo_for(std::clamp(r[c], 0.f, 1.f));
        ss[c] = rho / l[c];
        sa[c] = (1.f - rho) / l[c];
    }
    sigma_a = {sa[0], sa[1], sa[2]};
    sigma_s = {ss[0], ss[1], ss[2]};
}

void Subsurface::coefficients(const Material& m, RGB& sa, RGB& ss) const {
    if (from_reflectance && m.texture >= 0) {
        subsurface_from_reflectance(*table, m.base_color, mfp, sa, ss);
    } else {
        sa = sigma_a;
        ss = sigma_s;
    }
}

}  // namespace foton
