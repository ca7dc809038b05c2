#include "engine/scene/scene.h"

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

std::shared_ptr<const BssrdfTable> Scene::subsurface_table(float g, float eta) {
    for (const Subsurface& other : subsurfaces)
        if (other.table->g == g && other.table->eta == eta) return other.table;
    return std::make_shared<const BssrdfTable>(BssrdfTable::compute(g, eta));
}

uint32_t Scene::add_subsurface(const Subsurface& s, const std::string& file, int line) {
    if (subsurface_file.empty()) {
        subsurface_file = file;
        subsurface_line = line;
    }
    subsurfaces.push_back(s);
    return uint32_t(subsurfaces.size() - 1);
}

}  // namespace foton
