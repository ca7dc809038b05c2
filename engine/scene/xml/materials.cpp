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
float Loader::roughness(const pugi::xml_node& n) const {
    const float a = positive(n, "roughness", 0.2f);
    if (a < 2e-3f || a > 2.f)
        fail(n,
             "roughness must be in [0.002, 2] (use a specular conductor or dielectric for "
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
    if (d == "ashikhmin_shirley" || d == "anisotropic") {
        return MicrofacetDistribution::ashikhmin_shirley(exponent(n, "nu", 100.f),
                                                         exponent(n, "nv", 100.f));
    }
    fail(n, "unknown distribution '" + d + "' (blinn, beckmann, ashikhmin_shirley)");
}

Material Loader::material(const pugi::xml_node& n, bool top) {
    Material m;
    const std::string type = n.attribute("type").value();
    m.name = type;
    // Attributes and children every physically based material accepts.
    const Names common_children = {"emission", "texture"};
    // A texture multiplies the diffuse colour, which is then 1 unless given.
    const RGB diffuse_default{n.child("texture") ? 1.f : 0.5f};
    auto with = [](Names a, Names b) {
        std::vector<const char*> v(a.begin(), a.end());
        v.insert(v.end(), b.begin(), b.end());
        return v;
    };
    auto check_v = [&](const std::vector<const char*>& attrs,
                       const std::vector<const char*>& children) {
        for (const pugi::xml_attribute& a : n.attributes())
            if (std::none_of(attrs.begin(), attrs.end(),
                             [&](const char* s) { return std::string_view(s) == a.name(); }))
                fail(n, std::string("unknown attribute '") + a.name() + "' on <material type=\"" +
                            type + "\">");
        for (const pugi::xml_node& c : n.children()) {
            if (c.type() != pugi::node_element) continue;
            if (std::none_of(children.begin(), children.end(),
                             [&](const char* s) { return std::string_view(s) == c.name(); }))
                fail(c, std::string("unknown element <") + c.name() + "> in <material type=\"" +
                            type + "\">");
        }
    };
    auto attrs = [&](Names a) {
        std::vector<const char*> v = with({"type"}, a);
        if (!top) v.push_back("weight");
        return v;
    };
    if (type == "matte" || type == "phong" || type == "reflective" || type == "glass") {
        if (type == "matte") {
            m.type = MaterialType::Matte;
            check_v(attrs({"c_ambient", "c_diffuse"}), with({"base_color"}, common_children));
        } else if (type == "phong") {
            m.type = MaterialType::Phong;
            check_v(attrs({"c_ambient", "c_diffuse", "c_specular", "exp"}),
                    with({"base_color", "specular_color"}, common_children));
        } else if (type == "reflective") {
            m.type = MaterialType::Reflective;
            check_v(attrs({"c_ambient", "c_diffuse", "c_specular", "exp", "c_reflective"}),
                    with({"base_color", "specular_color", "reflective_color"}, common_children));
        } else {
            m.type = MaterialType::Glass;
            check_v(attrs({"ior"}), with({"refraction_color"}, common_children));
        }
        m.c_ambient = non_negative(n, "c_ambient", 0.f);
        m.c_diffuse = non_negative(n, "c_diffuse", m.type == MaterialType::Glass ? 0.f : 1.f);
        m.c_specular = non_negative(n, "c_specular", 1.f);
        m.exponent = exponent(n, "exp", 10.f);
        m.c_reflective = non_negative(n, "c_reflective", 1.f);
        m.ior = positive(n, "ior", 1.5f);
        m.base_color =
            rgb_child(n, "base_color", m.type == MaterialType::Glass ? RGB{0.f} : diffuse_default);
        m.specular_color = rgb_child(n, "specular_color", RGB{0.f});
        m.reflective_color = rgb_child(n, "reflective_color", RGB{1.f});
        m.refraction_color = rgb_child(n, "refraction_color", RGB{1.f});
        // The physically based reading of the thesis' models.
        if (m.type != MaterialType::Glass && m.c_diffuse > 0.f)
            m.bsdf.add(Lobe::lambert(m.base_color * m.c_diffuse));
        if ((m.type == MaterialType::Phong || m.type == MaterialType::Reflective) &&
            !(m.specular_color * m.c_specular).is_black())
            m.bsdf.add(Lobe::phong(m.specular_color * m.c_specular, m.exponent));
        if (m.type == MaterialType::Reflective)
            m.bsdf.add(Lobe::mirror(m.reflective_color * m.c_reflective, Fresnel{}));
        if (m.type == MaterialType::Glass)
            m.bsdf.add(Lobe::dielectric(m.ior, RGB{1.f}, m.refraction_color));
    } else {
        m.type = MaterialType::Generic;
        m.c_diffuse = 0.f;
        m.base_color = RGB{0.f};
        if (type == "lambert") {
            check_v(attrs({}), with({"reflectance"}, common_children));
            const RGB r = rgb_child(n, "reflectance", diffuse_default);
            if (r.max_component() > 1.f)
                fail(n.child("reflectance"), "reflectance must be in [0, 1] (energy would grow)");
            m.bsdf.add(Lobe::lambert(r));
            m.base_color = r;
            m.c_diffuse = 1.f;
        } else if (type == "oren_nayar") {
            check_v(attrs({"sigma"}), with({"reflectance"}, common_children));
            const RGB r = rgb_child(n, "reflectance", diffuse_default);
            if (r.max_component() > 1.f)
                fail(n.child("reflectance"), "reflectance must be in [0, 1] (energy would grow)");
            const float sigma = non_negative(n, "sigma", 0.3f);
            if (sigma > 1.6f) fail(n, "sigma is in radians and must be at most 1.6");
            m.bsdf.add(Lobe::oren_nayar(r, sigma));
            m.base_color = r;
            m.c_diffuse = 1.f;
        } else if (type == "conductor") {
            check_v(attrs({"preset", "roughness", "distribution", "exponent", "nu", "nv"}),
                    with({"eta", "k", "reflectance"}, common_children));
            const Fresnel f = conductor_fresnel(n);
            const bool rough = n.attribute("roughness") && number(n, "roughness") > 0.f;
            if (rough || n.attribute("distribution"))
                m.bsdf.add(Lobe::microfacet(RGB{1.f}, distribution(n, "beckmann"), f));
            else
                m.bsdf.add(Lobe::mirror(RGB{1.f}, f));
        } else if (type == "dielectric") {
            check_v(attrs({"ior", "roughness"}),
                    with({"reflectance", "transmittance"}, common_children));
            if (n.attribute("roughness") && number(n, "roughness") != 0.f)
                fail(n, "rough dielectrics are not supported (roughness must be 0)");
            m.ior = positive(n, "ior", 1.5f);
            m.bsdf.add(Lobe::dielectric(m.ior, rgb_child(n, "reflectance", RGB{1.f}),
                                        rgb_child(n, "transmittance", RGB{1.f})));
        } else if (type == "microfacet") {
            check_v(attrs({"model", "distribution", "roughness", "exponent", "nu", "nv", "fresnel",
                           "ior", "preset", "kd", "ks"}),
                    with({"specular", "diffuse", "eta", "k", "reflectance"}, common_children));
            const std::string model =
                n.attribute("model") ? n.attribute("model").value() : "torrance_sparrow";
            if (model != "torrance_sparrow" && model != "cook_torrance")
                fail(n,
                     "unknown microfacet model '" + model + "' (torrance_sparrow, cook_torrance)");
            const std::string fk =
                n.attribute("fresnel") ? n.attribute("fresnel").value() : "dielectric";
            Fresnel f;
            if (fk == "dielectric") {
                f.kind = FresnelKind::Dielectric;
                f.ior = positive(n, "ior", 1.5f);
            } else if (fk == "conductor") {
                f = conductor_fresnel(n);
            } else if (fk != "none") {
                fail(n, "unknown fresnel '" + fk + "' (dielectric, conductor, none)");
            }
            const MicrofacetDistribution d =
                distribution(n, model == "cook_torrance" ? "beckmann" : "blinn");
            const float ks = non_negative(n, "ks", 1.f);
            const RGB spec = rgb_child(n, "specular", RGB{1.f}) * ks;
            if (model == "cook_torrance") {
                // Cook–Torrance: kd * Lambert + ks * microfacet specular, kd + ks <= 1.
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
        } else if (type == "mix") {
            check_v(attrs({}), with({"material"}, common_children));
            // Mixes nest by recursion: a bound keeps a hostile file from exhausting the stack.
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
                if (!sub.emission.is_black())
                    fail(c, "put <emission> on the mix, not on its components");
                sub.bsdf.scale(w);
                if (sub.texture >= 0) {
                    if (m.texture >= 0)
                        fail(c,
                             "a mix takes one textured component (the texture multiplies its "
                             "lobes)");
                    m.texture = sub.texture;
                    m.textured_lobes = uint8_t(sub.textured_lobes << m.bsdf.size());
                }
                for (int i = 0; i < sub.bsdf.size(); ++i)
                    if (!m.bsdf.add(sub.bsdf.lobe(i)))
                        fail(c, "a mix may hold at most " + std::to_string(Bsdf::kMaxLobes) +
                                    " lobes");
                m.base_color += sub.base_color * (w * sub.c_diffuse);
            }
            if (total == 0.f) fail(n, "a mix needs at least one <material> with weight > 0");
            if (total > 1.f + 1e-5f) fail(n, "mix weights sum to more than 1 (energy would grow)");
            m.c_diffuse = 1.f;
        } else {
            fail(n, "unknown material type '" + type +
                        "' (matte, phong, reflective, glass, lambert, oren_nayar, conductor, "
                        "dielectric, microfacet, mix)");
        }
    }
    if (const pugi::xml_node tx = n.child("texture")) {
        // The diffuse reflectance's texture: the Lambert or Oren-Nayar lobe (the first one the
        // diffuse types add) and the base colour are multiplied by it.
        const bool diffuse = type == "matte" || type == "phong" || type == "reflective" ||
                             type == "lambert" || type == "oren_nayar";
        if (!diffuse)
            fail(tx,
                 "<texture> multiplies a diffuse reflectance: matte, phong, reflective, "
                 "lambert or oren_nayar (or put it on a mix's component)");
        if (m.bsdf.empty() || (m.bsdf.lobe(0).type != LobeType::Lambert &&
                               m.bsdf.lobe(0).type != LobeType::OrenNayar))
            fail(tx, "<texture> on a material without diffuse reflection (c_diffuse 0)");
        m.texture = parse_texture(tx);
        m.textured_lobes = 1;
    }
    if (const pugi::xml_node e = n.child("emission")) {
        check(e, {"r", "g", "b", "intensity", "sampling", "two_sided"}, {});
        m.emission =
            rgb(e, {"intensity", "sampling", "two_sided"}) * non_negative(e, "intensity", 1.f);
        m.emission_two_sided = boolean(e, "two_sided", false);
        if (e.attribute("sampling")) {
            const std::string sm = e.attribute("sampling").value();
            if (sm == "area")
                m.emitter_solid_angle = false;
            else if (sm != "solid_angle")
                fail(e, "unknown emitter sampling '" + sm + "' (area, solid_angle)");
        }
    }
    return m;
}

// <texture src="image" .../> or <texture type="checkerboard">: into Scene::textures.
int32_t Loader::parse_texture(const pugi::xml_node& tx) {
    const std::string kind = tx.attribute("type") ? tx.attribute("type").value() : "image";
    Texture t;
    t.su = number(tx, "scale_u", 1.f);
    t.sv = number(tx, "scale_v", 1.f);
    t.du = number(tx, "offset_u", 0.f);
    t.dv = number(tx, "offset_v", 0.f);
    if (kind == "image") {
        check(tx, {"type", "src", "encoding", "scale_u", "scale_v", "offset_u", "offset_v"}, {});
        const std::string src = tx.attribute("src").value();
        if (src.empty()) fail(tx, "<texture> needs attribute 'src' (or type=\"checkerboard\")");
        const std::string enc =
            tx.attribute("encoding") ? tx.attribute("encoding").value() : "srgb";
        if (enc != "srgb" && enc != "linear")
            fail(tx, "unknown texture encoding '" + enc + "' (srgb, linear)");
        const std::string path = (std::filesystem::path(base_) / src).string();
        const std::string key = path + (enc == "linear" ? "#linear" : "");
        t.kind = TextureKind::Image;
        if (const auto it = images_.find(key); it != images_.end()) {
            t.image = it->second;
        } else {
            try {
                scene_.texture_images.push_back(load_texture_image(path, enc == "linear"));
            } catch (const InputError& e) {
                fail(tx, "texture '" + src + "': " + e.what());
            }
            t.image = images_[key] = uint32_t(scene_.texture_images.size() - 1);
        }
    } else if (kind == "checkerboard") {
        check(tx, {"type", "scale_u", "scale_v", "offset_u", "offset_v"}, {"even", "odd"});
        t.kind = TextureKind::Checkerboard;
        t.value = rgb_child(tx, "even", RGB{1.f});
        t.other = rgb_child(tx, "odd", RGB{0.f});
        if (t.value.max_component() > 1.f || t.other.max_component() > 1.f)
            fail(tx, "checkerboard colours must be in [0, 1] (they multiply a reflectance)");
    } else {
        fail(tx, "unknown texture type '" + kind + "' (image, checkerboard)");
    }
    scene_.textures.push_back(t);
    return int32_t(scene_.textures.size() - 1);
}

}  // namespace foton::xml
