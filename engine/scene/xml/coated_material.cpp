// <material type="coated_diffuse"> and <material type="coated_conductor">: a dielectric coat
// over a Lambertian or conductor base with an optional medium between them (pbrt-v4's
// coateddiffuse and coatedconductor; the lobe is coated.cpp's random walk).
#include "loader.h"

namespace foton::xml {

namespace {
// The walk's per-evaluation counts fit the lobe's bytes; pbrt-v4's defaults are 10 and 1.
constexpr uint32_t kMaxCoatDepth = 100, kMaxCoatSamples = 64;
}  // namespace

CoatLayer Loader::coat_layer(const pugi::xml_node& n) const {
    CoatLayer c;
    c.ior = positive(n, "ior", 1.5f);
    c.thickness = positive(n, "thickness", 0.01f);
    c.g = number(n, "g", 0.f);
    if (!(c.g > -1.f && c.g < 1.f)) fail(n, "attribute 'g' must be in (-1, 1)");
    c.albedo = rgb_child(n, "albedo", RGB{0.f});
    if (c.albedo.max_component() > 1.f || std::min({c.albedo.r, c.albedo.g, c.albedo.b}) < 0.f)
        fail(n.child("albedo"), "the medium's albedo must be in [0, 1]");
    const uint32_t depth = count(n, "max_depth", 10), samples = count(n, "samples", 1);
    if (depth > kMaxCoatDepth)
        fail(n, "max_depth must be at most " + std::to_string(kMaxCoatDepth));
    if (samples > kMaxCoatSamples)
        fail(n, "samples must be at most " + std::to_string(kMaxCoatSamples));
    c.max_depth = uint8_t(depth);
    c.samples = uint8_t(samples);
    // The coat: smooth unless a roughness (GGX alpha, anisotropic with roughness_v) is given.
    const bool rough =
        (n.attribute("roughness") && number(n, "roughness") != 0.f) || n.attribute("roughness_v");
    c.coat_smooth = !rough;
    if (rough) {
        const float ax = roughness(n);
        const float ay = n.attribute("roughness_v") ? roughness(n, "roughness_v") : ax;
        c.coat = MicrofacetDistribution::trowbridge_reitz(ax, ay);
    }
    return c;
}

void Loader::coated_material(const pugi::xml_node& n, bool top, Material& m) {
    generic(m);
    const bool conductor = std::string_view(n.attribute("type").value()) == "coated_conductor";
    if (conductor)
        check_material(n, top,
                       {"ior", "roughness", "roughness_v", "thickness", "g", "max_depth", "samples",
                        "preset", "base_roughness", "base_roughness_v"},
                       {"albedo", "eta", "k", "reflectance"});
    else
        check_material(
            n, top, {"ior", "roughness", "roughness_v", "thickness", "g", "max_depth", "samples"},
            {"albedo", "reflectance"});
    const CoatLayer c = coat_layer(n);
    if (!conductor) {
        const RGB r = rgb_child(n, "reflectance", RGB{n.child("texture") ? 1.f : 0.5f});
        if (r.max_component() > 1.f) fail(n.child("reflectance"), "reflectance must be in [0, 1]");
        m.bsdf.add(Lobe::coated_diffuse(r, c));
        m.base_color = r;
        m.c_diffuse = 1.f;
        return;
    }
    // The base's index is relative to the coat it lies under.
    Fresnel f = conductor_fresnel(n);
    f.eta *= 1.f / c.ior;
    f.k *= 1.f / c.ior;
    const bool rough = (n.attribute("base_roughness") && number(n, "base_roughness") != 0.f) ||
                       n.attribute("base_roughness_v");
    MicrofacetDistribution d = MicrofacetDistribution::trowbridge_reitz(0.f, 0.f);
    if (rough) {
        const float ax = roughness(n, "base_roughness");
        const float ay = n.attribute("base_roughness_v") ? roughness(n, "base_roughness_v") : ax;
        d = MicrofacetDistribution::trowbridge_reitz(ax, ay);
    }
    m.bsdf.add(Lobe::coated_conductor(f, !rough, d, c));
}

}  // namespace foton::xml
