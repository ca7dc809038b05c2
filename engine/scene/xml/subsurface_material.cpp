// <material type="subsurface">: a dielectric boundary (ior, smooth or with a GGX roughness)
// over a scattering medium given by <sigma_a> and <sigma_s> (per unit length), or by a
// diffuse <reflectance> and <mfp> (mean free path), each times `scale`; `g` its phase
// asymmetry; or by a measured medium's name, preset="Skin1" (measured_media.h). Light under the
// surface is followed by the BSSRDF (scene/subsurface/), which only type="volpath" traces.
#include "engine/scene/measured_media.h"
#include "loader.h"

namespace foton::xml {

void Loader::subsurface_material(const pugi::xml_node& n, bool top, Material& m) {
    generic(m);
    if (!top) fail(n, "a subsurface material cannot be a component of a mix");
    check_material(n, top,
                   {"ior", "g", "scale", "roughness", "roughness_v", "distribution", "preset"},
                   {"sigma_a", "sigma_s", "reflectance", "mfp"});
    if (n.child("texture") || n.child("emission"))
        fail(n, "a subsurface material takes neither a texture nor an emission");
    m.ior = positive(n, "ior", 1.33f);
    const float g = number(n, "g", 0.f), scale = positive(n, "scale", 1.f);
    if (!(g > -1.f && g < 1.f)) fail(n, "g must be in (-1, 1)");
    const bool by_sigma = n.child("sigma_a") || n.child("sigma_s");
    const bool by_reflectance = n.child("reflectance") || n.child("mfp");
    // A measured medium (measured_media.h, per mm: scale converts to the scene's units).
    const MeasuredMedium* preset = nullptr;
    if (n.attribute("preset")) {
        preset = find_measured_medium(n.attribute("preset").value());
        if (!preset)
            fail(n, std::string("unknown preset '") + n.attribute("preset").value() + "' (" +
                        measured_media_names() + ")");
        if (g != 0.f) fail(n, "a preset's coefficients are the reduced ones: g must be 0");
    }
    if (int(by_sigma) + int(by_reflectance) + int(preset != nullptr) != 1)
        fail(n, "give <sigma_a> and <sigma_s>, <reflectance> and <mfp>, or a preset");
    Subsurface s;
    s.eta = m.ior;
    s.table = scene_.subsurface_table(g, m.ior);
    if (preset) {
        s.sigma_a = preset->sigma_a * scale;
        s.sigma_s = preset->sigma_s * scale;
    } else if (by_sigma) {
        if (!n.child("sigma_a") || !n.child("sigma_s"))
            fail(n, "give both <sigma_a> and <sigma_s>");
        s.sigma_a = rgb_child(n, "sigma_a", RGB{0.f}) * scale;
        s.sigma_s = rgb_child(n, "sigma_s", RGB{0.f}) * scale;
    } else {
        const RGB r = rgb_child(n, "reflectance", RGB{0.5f});
        const RGB mfp = rgb_child(n, "mfp", RGB{1.f}) * scale;
        if (r.max_component() > 1.f) fail(n, "<reflectance> must be at most 1 per channel");
        if (!(mfp.r > 0.f && mfp.g > 0.f && mfp.b > 0.f)) fail(n, "<mfp> must be positive");
        subsurface_from_reflectance(*s.table, r, mfp, s.sigma_a, s.sigma_s);
    }
    if (!((s.sigma_a + s.sigma_s).max_component() > 0.f))
        fail(n, "the medium must scatter or absorb (sigma_a + sigma_s > 0)");
    const bool rough =
        (n.attribute("roughness") && number(n, "roughness") != 0.f) || n.attribute("roughness_v");
    if (rough) {
        const MicrofacetDistribution d = distribution(n, "ggx");
        if (d.kind != MicrofacetKind::TrowbridgeReitz)
            fail(n, "a rough subsurface boundary takes distribution=\"ggx\"");
        m.bsdf.add(Lobe::rough_dielectric(m.ior, d, RGB{1.f}, RGB{1.f}));
    } else {
        m.bsdf.add(Lobe::dielectric(m.ior, RGB{1.f}, RGB{1.f}));
    }
    m.subsurface = int32_t(scene_.add_subsurface(s, name_, line_of(n)));
}

}  // namespace foton::xml
