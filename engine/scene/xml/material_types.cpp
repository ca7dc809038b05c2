// The readers of each <material type="...">: each checks its element's attributes and
// children (Loader::check_material) and adds the type's lobes and colours.
#include "loader.h"

namespace foton::xml {

namespace {
// A texture multiplies the diffuse colour, which is then 1 unless given.
RGB diffuse_default(const pugi::xml_node& n) {
    return RGB{n.child("texture") ? 1.f : 0.5f};
}
}  // namespace

// The first thesis' models (matte, phong, reflective, glass) and their physically based
// reading as lobes.
void Loader::thesis_material(const pugi::xml_node& n, bool top, Material& m) {
    const std::string type = n.attribute("type").value();
    if (type == "matte") {
        m.type = MaterialType::Matte;
        check_material(n, top, {"c_ambient", "c_diffuse"}, {"base_color"});
    } else if (type == "phong") {
        m.type = MaterialType::Phong;
        check_material(n, top, {"c_ambient", "c_diffuse", "c_specular", "exp"},
                       {"base_color", "specular_color"});
    } else if (type == "reflective") {
        m.type = MaterialType::Reflective;
        check_material(n, top, {"c_ambient", "c_diffuse", "c_specular", "exp", "c_reflective"},
                       {"base_color", "specular_color", "reflective_color"});
    } else {
        m.type = MaterialType::Glass;
        check_material(n, top, {"ior"}, {"refraction_color"});
    }
    const bool glass = m.type == MaterialType::Glass;
    m.c_ambient = non_negative(n, "c_ambient", 0.f);
    m.c_diffuse = non_negative(n, "c_diffuse", glass ? 0.f : 1.f);
    m.c_specular = non_negative(n, "c_specular", 1.f);
    m.exponent = exponent(n, "exp", 10.f);
    m.c_reflective = non_negative(n, "c_reflective", 1.f);
    m.ior = positive(n, "ior", 1.5f);
    m.base_color = rgb_child(n, "base_color", glass ? RGB{0.f} : diffuse_default(n));
    m.specular_color = rgb_child(n, "specular_color", RGB{0.f});
    m.reflective_color = rgb_child(n, "reflective_color", RGB{1.f});
    m.refraction_color = rgb_child(n, "refraction_color", RGB{1.f});
    if (!glass && m.c_diffuse > 0.f) m.bsdf.add(Lobe::lambert(m.base_color * m.c_diffuse));
    if ((m.type == MaterialType::Phong || m.type == MaterialType::Reflective) &&
        !(m.specular_color * m.c_specular).is_black())
        m.bsdf.add(Lobe::phong(m.specular_color * m.c_specular, m.exponent));
    if (m.type == MaterialType::Reflective)
        m.bsdf.add(Lobe::mirror(m.reflective_color * m.c_reflective, Fresnel{}));
    if (glass) m.bsdf.add(Lobe::dielectric(m.ior, RGB{1.f}, m.refraction_color));
}

// lambert and oren_nayar: a diffuse reflectance in [0, 1].
void Loader::lambert_material(const pugi::xml_node& n, bool top, Material& m) {
    generic(m);
    const bool oren_nayar = std::string_view(n.attribute("type").value()) == "oren_nayar";
    if (oren_nayar)
        check_material(n, top, {"sigma"}, {"reflectance"});
    else
        check_material(n, top, {}, {"reflectance"});
    const RGB r = rgb_child(n, "reflectance", diffuse_default(n));
    if (r.max_component() > 1.f)
        fail(n.child("reflectance"), "reflectance must be in [0, 1] (energy would grow)");
    if (oren_nayar) {
        const float sigma = non_negative(n, "sigma", 0.3f);
        if (sigma > 1.6f) fail(n, "sigma is in radians and must be at most 1.6");
        m.bsdf.add(Lobe::oren_nayar(r, sigma));
    } else {
        m.bsdf.add(Lobe::lambert(r));
    }
    m.base_color = r;
    m.c_diffuse = 1.f;
}

// Paper, leaves, lamp shades: a Lambert lobe of reflectance R and a diffuse transmission lobe
// of transmittance T on the far side (pbrt-v4's diffusetransmission).
void Loader::diffuse_transmission_material(const pugi::xml_node& n, bool top, Material& m) {
    generic(m);
    check_material(n, top, {}, {"reflectance", "transmittance"});
    const RGB r = rgb_child(n, "reflectance", RGB{0.25f});
    const RGB t = rgb_child(n, "transmittance", RGB{0.25f});
    if ((r + t).max_component() > 1.f)
        fail(n, "reflectance + transmittance must be at most 1 per channel (energy would grow)");
    if (!r.is_black()) m.bsdf.add(Lobe::lambert(r));
    if (!t.is_black()) m.bsdf.add(Lobe::lambert_transmission(t));
    m.base_color = r;
    m.c_diffuse = 1.f;
}

// pbrt-v4's "interface": no surface at all, only the boundary of a medium (the object's
// medium_inside and medium_outside say which); rays pass it unchanged.
void Loader::interface_material(const pugi::xml_node& n, bool top, Material& m) {
    generic(m);
    if (!top) fail(n, "an interface material cannot be a component of a mix");
    check_material(n, top, {}, {});
    if (n.child("emission") || n.child("texture"))
        fail(n, "an interface material neither emits nor takes a texture (it is no surface)");
    m.is_interface = true;
    scene_.mark_volumetric(name_, line_of(n));
}

void Loader::conductor_material(const pugi::xml_node& n, bool top, Material& m) {
    generic(m);
    check_material(n, top,
                   {"preset", "roughness", "roughness_v", "distribution", "exponent", "nu", "nv"},
                   {"eta", "k", "reflectance"});
    const Fresnel f = conductor_fresnel(n);
    const bool rough = n.attribute("roughness") && number(n, "roughness") > 0.f;
    if (rough || n.attribute("distribution"))
        m.bsdf.add(Lobe::microfacet(RGB{1.f}, distribution(n, "beckmann"), f));
    else
        m.bsdf.add(Lobe::mirror(RGB{1.f}, f));
}

void Loader::dielectric_material(const pugi::xml_node& n, bool top, Material& m) {
    generic(m);
    check_material(n, top, {"ior", "roughness", "roughness_v", "distribution"},
                   {"reflectance", "transmittance"});
    m.ior = positive(n, "ior", 1.5f);
    const RGB reflect = rgb_child(n, "reflectance", RGB{1.f});
    const RGB transmit = rgb_child(n, "transmittance", RGB{1.f});
    // Rough glass: Walter et al.'s microfacet interface, Trowbridge–Reitz (GGX) only.
    const bool rough =
        (n.attribute("roughness") && number(n, "roughness") != 0.f) || n.attribute("roughness_v");
    if (!rough) {
        if (n.attribute("distribution")) fail(n, "a distribution needs a roughness above 0");
        m.bsdf.add(Lobe::dielectric(m.ior, reflect, transmit));
        return;
    }
    const MicrofacetDistribution d = distribution(n, "ggx");
    if (d.kind != MicrofacetKind::TrowbridgeReitz)
        fail(n, "a rough dielectric takes distribution=\"ggx\" (Walter et al.'s model)");
    m.bsdf.add(Lobe::rough_dielectric(m.ior, d, reflect, transmit));
}

// Torrance–Sparrow (specular only) or Cook–Torrance (kd * Lambert + ks * specular).
void Loader::microfacet_material(const pugi::xml_node& n, bool top, Material& m) {
    generic(m);
    check_material(n, top,
                   {"model", "distribution", "roughness", "roughness_v", "exponent", "nu", "nv",
                    "fresnel", "ior", "preset", "kd", "ks"},
                   {"specular", "diffuse", "eta", "k", "reflectance"});
    const std::string model =
        n.attribute("model") ? n.attribute("model").value() : "torrance_sparrow";
    if (model != "torrance_sparrow" && model != "cook_torrance")
        fail(n, "unknown microfacet model '" + model + "' (torrance_sparrow, cook_torrance)");
    const std::string fk = n.attribute("fresnel") ? n.attribute("fresnel").value() : "dielectric";
    Fresnel f;
    if (fk == "dielectric") {
        f.kind = FresnelKind::Dielectric;
        f.ior = positive(n, "ior", 1.5f);
    } else if (fk == "conductor") {
        f = conductor_fresnel(n);
    } else if (fk == "schlick") {
        // F0 of the conductor the element describes, or of a dielectric of index ior.
        const bool metal =
            n.attribute("preset") || n.child("eta") || n.child("k") || n.child("reflectance");
        if (metal) {
            f = Fresnel::schlick(conductor_fresnel(n).eval(1.f));
        } else {
            const float ior = positive(n, "ior", 1.5f);
            const float r = (ior - 1.f) / (ior + 1.f);
            f = Fresnel::schlick(RGB{r * r});
        }
    } else if (fk != "none") {
        fail(n, "unknown fresnel '" + fk + "' (dielectric, conductor, schlick, none)");
    }
    const MicrofacetDistribution d =
        distribution(n, model == "cook_torrance" ? "beckmann" : "blinn");
    const float ks = non_negative(n, "ks", 1.f);
    const RGB spec = rgb_child(n, "specular", RGB{1.f}) * ks;
    if (model == "cook_torrance") {
        // kd + ks <= 1.
        const float kd = non_negative(n, "kd", n.child("diffuse") ? 1.f - ks : 0.f);
        if (kd + ks > 1.f + 1e-5f) fail(n, "kd + ks must be at most 1");
        const RGB diff = rgb_child(n, "diffuse", RGB{0.5f}) * kd;
        if (!diff.is_black()) m.bsdf.add(Lobe::lambert(diff));
        m.base_color = diff;
        m.c_diffuse = 1.f;
    } else if (n.child("diffuse") || n.attribute("kd")) {
        fail(n, "a diffuse part belongs to model=\"cook_torrance\" (or use a mix)");
    }
    m.bsdf.add(Lobe::microfacet(spec, d, f));
}

// A weighted sum of materials (weights summing to at most 1), nested by recursion.
void Loader::mix_material(const pugi::xml_node& n, bool top, Material& m) {
    generic(m);
    check_material(n, top, {}, {"material"});
    // A bound keeps a hostile file from exhausting the stack.
    if (mix_depth_ >= kMaxMixDepth)
        fail(n, "mixes nest at most " + std::to_string(kMaxMixDepth) + " deep");
    ++mix_depth_;
    struct Leave {
        int& depth;
        ~Leave() { --depth; }
    } leave{mix_depth_};
    float total = 0.f;
    for (const pugi::xml_node& c : n.children("material")) {
        const float w = non_negative(c, "weight", 1.f);
        total += w;
        Material sub = material(c, false);
        if (sub.normal_map >= 0) {
            // One shading frame for the mixture's lobes.
            if (m.normal_map >= 0) fail(c, "a mix takes one normal-mapped component");
            m.normal_map = sub.normal_map;
        }
        if (!sub.emission.is_black()) fail(c, "put <emission> on the mix, not on its components");
        sub.bsdf.scale(w);
        if (sub.texture >= 0) {
            if (m.texture >= 0)
                fail(c, "a mix takes one textured component (the texture multiplies its lobes)");
            m.texture = sub.texture;
            m.textured_lobes = uint8_t(sub.textured_lobes << m.bsdf.size());
        }
        for (int i = 0; i < sub.bsdf.size(); ++i)
            if (!m.bsdf.add(sub.bsdf.lobe(i)))
                fail(c, "a mix may hold at most " + std::to_string(Bsdf::kMaxLobes) + " lobes");
        m.base_color += sub.base_color * (w * sub.c_diffuse);
    }
    if (total == 0.f) fail(n, "a mix needs at least one <material> with weight > 0");
    if (total > 1.f + 1e-5f) fail(n, "mix weights sum to more than 1 (energy would grow)");
    m.c_diffuse = 1.f;
}

}  // namespace foton::xml
