// <material> and its models, presets and microfacet distributions.
#include <filesystem>

#include "loader.h"

#include "engine/scene/metals.h"

namespace foton::xml {

uint32_t Loader::parse_material(const pugi::xml_node& object) {
    const pugi::xml_node n = child(object, "material");
    if (std::distance(object.children("material").begin(), object.children("material").end()) > 1)
        fail(n, "an object takes exactly one <material>");
    Material m = material(n, true);
    scene_.materials.push_back(m);
    return uint32_t(scene_.materials.size() - 1);
}

Fresnel Loader::conductor_fresnel(const pugi::xml_node& n) const {
    Fresnel f;
    f.kind = FresnelKind::Conductor;
    if (n.attribute("preset")) {
        const std::string p = n.attribute("preset").value();
        std::string names;
        for (const Metal& c : metals()) {
            if (p == c.name) {
                f.eta = c.eta;
                f.k = c.k;
                return f;
            }
            names += (names.empty() ? "" : ", ") + std::string(c.name);
        }
        fail(n, "unknown conductor preset '" + p + "' (" + names + ")");
    }
    if (n.child("eta") || n.child("k")) {
        f.eta = rgb_child(n, "eta", RGB{1.f});
        f.k = rgb_child(n, "k", RGB{0.f});
        if (!(f.eta.r > 0.f && f.eta.g > 0.f && f.eta.b > 0.f))
            fail(n.child("eta"), "conductor eta must be positive");
        return f;
    }
    const RGB r = rgb_child(n, "reflectance", RGB{1.f});
    if (r.max_component() > 1.f) fail(n.child("reflectance"), "reflectance must be in [0, 1]");
    return conductor_from_reflectance(r);
}

// The limits that keep every lobe finite in float (documented in scenes/README.md): a
// microfacet roughness in [2e-3, 2] (smoother is a specular lobe), an exponent in (0, 1e6].
float Loader::roughness(const pugi::xml_node& n, const char* attr) const {
    const float a = positive(n, attr, 0.2f);
    if (a < 2e-3f || a > 2.f)
        fail(n, std::string(attr) +
                    " must be in [0.002, 2] (use a specular conductor or dielectric for "
                    "smoother surfaces)");
    return a;
}

float Loader::exponent(const pugi::xml_node& n, const char* attr, float fallback) const {
    const float e = positive(n, attr, fallback);
    if (e > 1e6f) fail(n, std::string("attribute '") + attr + "' must be at most 1e6");
    return e;
}

MicrofacetDistribution Loader::distribution(const pugi::xml_node& n, const char* fallback) const {
    const std::string d =
        n.attribute("distribution") ? n.attribute("distribution").value() : fallback;
    if (d == "blinn") {
        float e = 0.f;
        if (n.attribute("exponent"))
            e = exponent(n, "exponent", 100.f);
        else {
            // Blinn's exponent with the same RMS slope as a Beckmann roughness alpha.
            const float a = roughness(n);
            e = std::max(0.f, 2.f / (a * a) - 2.f);
        }
        return MicrofacetDistribution::blinn(e);
    }
    if (d == "beckmann") return MicrofacetDistribution::beckmann(roughness(n));
    if (d == "ggx" || d == "trowbridge_reitz") {
        // alpha along the tangent, and across it when roughness_v is given (anisotropic).
        const float ax = roughness(n);
        const float ay = n.attribute("roughness_v") ? roughness(n, "roughness_v") : ax;
        return MicrofacetDistribution::trowbridge_reitz(ax, ay);
    }
    if (d == "ashikhmin_shirley" || d == "anisotropic") {
        return MicrofacetDistribution::ashikhmin_shirley(exponent(n, "nu", 100.f),
                                                         exponent(n, "nv", 100.f));
    }
    fail(n, "unknown distribution '" + d + "' (blinn, beckmann, ashikhmin_shirley, ggx)");
}

// The readers of each type, in the order the unknown-type message lists them.
const std::vector<Loader::MaterialReader>& Loader::material_readers() {
    static const std::vector<MaterialReader> readers = {
        {"matte", &Loader::thesis_material},
        {"phong", &Loader::thesis_material},
        {"reflective", &Loader::thesis_material},
        {"glass", &Loader::thesis_material},
        {"lambert", &Loader::lambert_material},
        {"oren_nayar", &Loader::lambert_material},
        {"conductor", &Loader::conductor_material},
        {"dielectric", &Loader::dielectric_material},
        {"microfacet", &Loader::microfacet_material},
        {"mix", &Loader::mix_material},
        {"diffuse_transmission", &Loader::diffuse_transmission_material},
        {"coated_diffuse", &Loader::coated_material},
        {"coated_conductor", &Loader::coated_material},
        {"interface", &Loader::interface_material},
        {"subsurface", &Loader::subsurface_material},
    };
    return readers;
}

Material Loader::material(const pugi::xml_node& n, bool top) {
    Material m;
    const std::string type = n.attribute("type").value();
    m.name = type;
    const MaterialReader* reader = nullptr;
    std::string names;
    for (const MaterialReader& r : material_readers()) {
        if (type == r.type) reader = &r;
        names += (names.empty() ? "" : ", ") + std::string(r.type);
    }
    if (!reader) fail(n, "unknown material type '" + type + "' (" + names + ")");
    (this->*reader->read)(n, top, m);
    material_texture(n, m);
    material_normal_map(n, m);
    material_bump(n, m);
    material_roughness_map(n, m);
    material_emission(n, m);
    return m;
}

void Loader::check_material(const pugi::xml_node& n, bool top, Names attrs, Names children) const {
    const std::string type = n.attribute("type").value();
    // Every material takes type (and a weight inside a mix), <emission>, <texture>,
    // <normal_map>, <bump> and <roughness_map>.
    auto known_attr = [&](const char* a) {
        return in(attrs, a) || std::string_view(a) == "type" ||
               (!top && std::string_view(a) == "weight");
    };
    for (const pugi::xml_attribute& a : n.attributes())
        if (!known_attr(a.name()))
            fail(n, std::string("unknown attribute '") + a.name() + "' on <material type=\"" +
                        type + "\">");
    for (const pugi::xml_node& c : n.children()) {
        if (c.type() != pugi::node_element) continue;
        const std::string_view name = c.name();
        if (!in(children, c.name()) && name != "emission" && name != "texture" &&
            name != "normal_map" && name != "bump" && name != "roughness_map")
            fail(c, std::string("unknown element <") + c.name() + "> in <material type=\"" + type +
                        "\">");
    }
}

void Loader::material_emission(const pugi::xml_node& n, Material& m) const {
    const pugi::xml_node e = n.child("emission");
    if (!e) return;
    check(e, {"r", "g", "b", "intensity", "sampling", "two_sided"}, {});
    m.emission = emitted(
        e, rgb(e, {"intensity", "sampling", "two_sided"}) * non_negative(e, "intensity", 1.f));
    m.emission_two_sided = boolean(e, "two_sided", false);
    if (e.attribute("sampling")) {
        const std::string sm = e.attribute("sampling").value();
        if (sm == "area")
            m.emitter_solid_angle = false;
        else if (sm != "solid_angle")
            fail(e, "unknown emitter sampling '" + sm + "' (area, solid_angle)");
    }
}

}  // namespace foton::xml
