// pbrt-v4's subsurface material: the medium under its surface, given by sigma_a and sigma_s,
// by a diffuse reflectance and mean free path, or by pbrt-v4's defaults (skim milk-like
// coefficients per mm), each times `scale`.
#include <algorithm>

#include "engine/scene/measured_media.h"
#include "importer.h"

namespace foton::pbrt {

namespace {

float smallest(const RGB& c) {
    return std::min({c.r, c.g, c.b});
}

}  // namespace

void Importer::subsurface_material(const Token& t, const ParamList& p, Material& m,
                                   const std::string& what) {
    // A measured medium by name (measured_media.h): its reduced coefficients, so g = 0.
    const MeasuredMedium* named = nullptr;
    if (p.has("name")) {
        named = find_measured_medium(p.text("name", ""));
        if (!named)
            fail(t, what + ": unknown name '" + p.text("name", "") + "' (" +
                        measured_media_names() + ")");
        if (p.has("sigma_a") || p.has("sigma_s") || p.has("reflectance"))
            fail(t, what + ": give a name, sigma_a and sigma_s, or a reflectance, not two");
        if (p.has("g") && p.real("g", 0.f) != 0.f)
            warn(file(), t.line,
                 what +
                     ": g ignored with a named medium (its coefficients "
                     "are the reduced ones)");
    }
    const float scale = p.real("scale", 1.f), eta = p.real("eta", 1.33f);
    const float g = named ? 0.f : p.real("g", 0.f);
    if (!(scale > 0.f && scale < 1e12f)) fail(t, what + ": scale must be in (0, 1e12)");
    if (!(g > -1.f && g < 1.f)) fail(t, what + ": g must be in (-1, 1)");
    if (!(eta > 0.f && eta < 10.f)) fail(t, what + ": eta must be in (0, 10)");
    if (p.has("sigma_a") != p.has("sigma_s"))
        fail(t, what + ": give both \"sigma_a\" and \"sigma_s\", or neither");
    Subsurface s;
    s.eta = eta;
    s.table = scene_.subsurface_table(g, eta);
    if (named) {
        s.sigma_a = named->sigma_a * scale;
        s.sigma_s = named->sigma_s * scale;
    } else if (p.has("sigma_a")) {
        s.sigma_a = *p.color("sigma_a", false) * scale;
        s.sigma_s = *p.color("sigma_s", false) * scale;
    } else if (p.has("reflectance")) {
        // A reflectance texture is read at each entry point (Subsurface::coefficients).
        const RGB r = reflectance(p, "reflectance", RGB{1.f}, what, m.texture);
        const auto mfp = p.color("mfp", false);
        s.mfp = (mfp ? *mfp : RGB{1.f}) * scale;
        if (!(smallest(s.mfp) > 0.f)) fail(t, what + ": mfp must be positive");
        s.from_reflectance = true;
        m.base_color = r;
        m.textured_lobes = 0;
        subsurface_from_reflectance(*s.table, r, s.mfp, s.sigma_a, s.sigma_s);
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
