// pbrt-v4's subsurface material: the medium under its surface, given by sigma_a and sigma_s,
// by a diffuse reflectance and mean free path, or by pbrt-v4's defaults (skim milk-like
// coefficients per mm), each times `scale`.
#include <algorithm>

#include "importer.h"

namespace foton::pbrt {

namespace {

float smallest(const RGB& c) {
    return std::min({c.r, c.g, c.b});
}

}  // namespace

void Importer::subsurface_material(const Token& t, const ParamList& p, Material& m,
                                   const std::string& what) {
    if (p.has("name"))
        fail(t, what +
                    ": named scattering presets are not supported (give sigma_a and "
                    "sigma_s, or reflectance and mfp)");
    const float scale = p.real("scale", 1.f), g = p.real("g", 0.f), eta = p.real("eta", 1.33f);
    if (!(scale > 0.f && scale < 1e12f)) fail(t, what + ": scale must be in (0, 1e12)");
    if (!(g > -1.f && g < 1.f)) fail(t, what + ": g must be in (-1, 1)");
    if (!(eta > 0.f && eta < 10.f)) fail(t, what + ": eta must be in (0, 10)");
    if (p.has("sigma_a") != p.has("sigma_s"))
        fail(t, what + ": give both \"sigma_a\" and \"sigma_s\", or neither");
    Subsurface s;
    s.eta = eta;
    s.table = scene_.subsurface_table(g, eta);
    if (p.has("sigma_a")) {
        s.sigma_a = *p.color("sigma_a", false) * scale;
        s.sigma_s = *p.color("sigma_s", false) * scale;
    } else if (p.has("reflectance")) {
        const RGB r = reflectance(p, "reflectance", RGB{1.f}, what);
        const auto mfp = p.color("mfp", false);
        const RGB free_path = (mfp ? *mfp : RGB{1.f}) * scale;
        if (!(smallest(free_path) > 0.f)) fail(t, what + ": mfp must be positive");
        subsurface_from_reflectance(*s.table, r, free_path, s.sigma_a, s.sigma_s);
    } else {
        s.sigma_a = RGB{0.0011f, 0.0024f, 0.014f} * scale;
        s.sigma_s = RGB{2.55f, 3.21f, 3.77f} * scale;
    }
    if (!(smallest(s.sigma_a) >= 0.f && smallest(s.sigma_s) >= 0.f))
        fail(t, what + ": sigma_a and sigma_s must not be negative");
    if (!((s.sigma_a + s.sigma_s).max_component() < 1e12f))
        fail(t, what + ": the extinction must be below 1e12");
    m.ior = eta;
    m.subsurface = int32_t(scene_.add_subsurface(s, file(), t.line));
}

}  // namespace foton::pbrt
