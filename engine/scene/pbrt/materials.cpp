// Material, MakeNamedMaterial and Texture: pbrt-v4's materials as foton BSDFs.
#include <cmath>

#include "engine/core/input_file.h"
#include "engine/scene/metals.h"
#include "importer.h"

namespace foton::pbrt {

const TextureDesc* Importer::texture_ref(const ParamList& p, const std::string& name,
                                         bool is_float) const {
    const std::string ref = p.texture(name);
    if (ref.empty()) return nullptr;
    const auto it = textures_.find(ref);
    if (it == textures_.end() || it->second.is_float != is_float)
        throw InputError(
            p.file, p.find(name)->line,
            std::string("unknown ") + (is_float ? "float" : "spectrum") + " texture '" + ref + "'");
    return &it->second;
}

RGB Importer::reflectance(const ParamList& p, const std::string& name, RGB fallback,
                          const std::string& what, int32_t& texture) {
    const TextureDesc* tx = texture_ref(p, name, false);
    texture = tx ? tx->scene_texture : -1;
    return texture >= 0 ? RGB{1.f} : reflectance(p, name, fallback, what);
}

RGB Importer::reflectance(const ParamList& p, const std::string& name, RGB fallback,
                          const std::string& what) {
    RGB c = fallback;
    if (const TextureDesc* tx = texture_ref(p, name, false)) {
        if (tx->scene_texture >= 0)
            throw InputError(p.file, p.find(name)->line,
                             what + ": a varying texture on '" + name + "' is not supported");
        c = tx->value;
    } else if (const auto v = p.color(name, false)) {
        c = *v;
    }
    if (c.max_component() > 1.f) {
        warn(p.file, p.find(name)->line,
             what + " " + name + " above 1 clamped to 1 (as pbrt-v4 does)");
        c = {std::min(c.r, 1.f), std::min(c.g, 1.f), std::min(c.b, 1.f)};
    }
    return c;
}

float Importer::float_value(const ParamList& p, const std::string& name, float fallback) {
    const TextureDesc* tx = texture_ref(p, name, true);
    return tx ? tx->value.r : p.real(name, fallback);
}

void Importer::texture(const Token& t, const std::string& name, const std::string& kind,
                       const std::string& type, const ParamList& p) {
    if (kind != "spectrum" && kind != "float")
        fail(t, "texture kind must be spectrum or float, not '" + kind + "'");
    TextureDesc tex;
    tex.type = type;
    tex.is_float = kind == "float";
    // A constant operand: a value, or a constant texture of this texture's kind.
    auto value = [&](const std::string& key, RGB fallback) {
        if (const TextureDesc* tx = texture_ref(p, key, tex.is_float)) {
            if (tx->scene_texture >= 0)
                fail(t, "'" + key + "': textures of varying textures are not supported");
            return tx->value;
        }
        if (tex.is_float) return RGB{p.real(key, fallback.r)};
        const auto c = p.color(key, false);
        return c ? *c : fallback;
    };
    if (type == "constant") {
        tex.value = value("value", RGB{1.f});
    } else if (type == "scale") {
        tex.value = value("tex", RGB{1.f}) * float_value(p, "scale", 1.f);
    } else if ((type == "imagemap" || type == "checkerboard") && !tex.is_float) {
        Texture st;
        if (type == "imagemap") {
            st.kind = TextureKind::Image;
            st.image = image_texture(t, p);
            st.scale = RGB{p.real("scale", 1.f)};
            if (p.boolean("invert", false)) fail(t, "inverted image textures are not supported");
        } else {
            if (p.integer("dimension", 2) != 2) fail(t, "only 2D checkerboards are supported");
            st.kind = TextureKind::Checkerboard;
            st.value = value("tex1", RGB{1.f});
            st.other = value("tex2", RGB{0.f});
        }
        const std::string mapping = p.text("mapping", "uv");
        if (mapping != "uv") fail(t, "texture mapping '" + mapping + "' is not supported (uv)");
        st.su = p.real("uscale", 1.f);
        st.sv = p.real("vscale", 1.f);
        st.du = p.real("udelta", 0.f);
        st.dv = p.real("vdelta", 0.f);
        scene_.textures.push_back(st);
        tex.scene_texture = int32_t(scene_.textures.size() - 1);
    } else {
        fail(t, "texture type '" + type + "' is not supported (constant, scale, and spectrum " +
                    "imagemap and checkerboard)");
    }
    textures_[name] = tex;
    warn_unused(p, "Texture \"" + name + "\"");
    count("Texture " + type);
}

uint32_t Importer::image_texture(const Token& t, const ParamList& p) {
    const std::string rel = p.text("filename", "");
    if (rel.empty()) fail(t, "imagemap needs \"string filename\"");
    const std::string wrap = p.text("wrap", "repeat");
    if (wrap != "repeat") fail(t, "texture wrap '" + wrap + "' is not supported (repeat)");
    const std::string filter = p.text("filter", "bilinear");
    if (filter != "bilinear")
        warn(file(), t.line, "texture filter '" + filter + "': foton filters bilinearly");
    p.real("maxanisotropy", 8.f);
    const std::string enc = p.text("encoding", "sRGB");
    if (enc != "sRGB" && enc != "linear") fail(t, "texture encoding '" + enc + "' (sRGB, linear)");
    return image_file(t, rel, enc == "linear");
}

uint32_t Importer::image_file(const Token& t, const std::string& rel, bool linear) {
    const std::string key = rel + (linear ? "#linear" : "");
    if (const auto it = images_.find(key); it != images_.end()) return it->second;
    const std::string path = input_path(t, "texture", rel, kMaxMeshFileBytes);
    try {
        scene_.texture_images.push_back(load_texture_image(path, linear));
    } catch (const InputError& e) {
        fail(t, std::string("texture '") + rel + "': " + e.what());
    }
    return images_[key] = uint32_t(scene_.texture_images.size() - 1);
}

namespace {

// pbrt-v4's roughness to microfacet alpha (remaproughness): alpha = sqrt(roughness).
float alpha_of(float roughness, bool remap) {
    return remap ? std::sqrt(std::max(roughness, 0.f)) : roughness;
}

}  // namespace

Material Importer::make_material(const Token& t, const std::string& type, const ParamList& p) {
    Material m;
    m.type = MaterialType::Generic;
    m.name = type;
    m.c_diffuse = 0.f;
    m.base_color = RGB{0.f};
    const std::string what = "Material \"" + type + "\"";
    // Rough lobes: pbrt's Trowbridge–Reitz of alpha_x, alpha_y (remapped from roughness as
    // pbrt-v4's remaproughness does). Below pbrt's smoothness limit (both under 1e-3):
    // specular.
    auto distribution = [&](bool& smooth, const std::string& prefix = "") {
        const bool remap = p.boolean("remaproughness", true);
        float u = float_value(p, prefix + "roughness", 0.f), v = u;
        if (p.has(prefix + "uroughness") || p.has(prefix + "vroughness")) {
            u = float_value(p, prefix + "uroughness", u);
            v = float_value(p, prefix + "vroughness", v);
        }
        const float ax = alpha_of(u, remap), ay = alpha_of(v, remap);
        smooth = std::max(ax, ay) < 1e-3f;
        if (!smooth && std::max(ax, ay) > 2.f) fail(t, what + ": roughness gives alpha above 2");
        return MicrofacetDistribution::trowbridge_reitz(std::clamp(ax, 1e-4f, 2.f),
                                                        std::clamp(ay, 1e-4f, 2.f));
    };
    // A conductor's Fresnel from `reflectance` or eta and k (pbrt-v4's default: copper).
    auto conductor_of = [&](const std::string& prefix) {
        if (p.has("reflectance"))
            return conductor_from_reflectance(reflectance(p, "reflectance", RGB{1.f}, what));
        const Metal& cu = metals()[2];
        const auto eta = p.color(prefix + "eta", false), k = p.color(prefix + "k", false);
        Fresnel f;
        f.kind = FresnelKind::Conductor;
        f.eta = eta ? *eta : cu.eta;
        f.k = k ? *k : cu.k;
        if (!(f.eta.r > 0.f && f.eta.g > 0.f && f.eta.b > 0.f))
            fail(t, what + ": " + prefix + "eta must be positive");
        return f;
    };
    if (type == "diffuse") {
        const RGB r = reflectance(p, "reflectance", RGB{0.5f}, what, m.texture);
        if (m.texture >= 0) m.textured_lobes = 1;
        if (!r.is_black()) m.bsdf.add(Lobe::lambert(r));
        m.base_color = r;
        m.c_diffuse = 1.f;
    } else if (type == "conductor") {
        const Fresnel f = conductor_of("");
        bool smooth = true;
        const MicrofacetDistribution d = distribution(smooth);
        if (smooth)
            m.bsdf.add(Lobe::mirror(RGB{1.f}, f));
        else
            m.bsdf.add(Lobe::microfacet(RGB{1.f}, d, f));
    } else if (type == "dielectric") {
        float eta = 1.5f;
        if (const Param* q = p.find("eta")) {
            if (q->type == "float") {
                eta = p.real("eta", 1.5f);
            } else {
                const auto c = p.color("eta", false);
                eta = c->g;
                warn(file(), q->line, what + ": a spectral eta is rendered without dispersion");
            }
        }
        if (!(eta > 0.f)) fail(t, what + ": eta must be positive");
        bool smooth = true;
        const MicrofacetDistribution d = distribution(smooth);
        m.ior = eta;
        if (smooth)
            m.bsdf.add(Lobe::dielectric(eta, RGB{1.f}, RGB{1.f}));
        else
            m.bsdf.add(Lobe::rough_dielectric(eta, d, RGB{1.f}, RGB{1.f}));
    } else if (type == "diffusetransmission") {
        const float scale = p.real("scale", 1.f);
        if (!(scale >= 0.f)) fail(t, what + ": scale must not be negative");
        const RGB r = reflectance(p, "reflectance", RGB{0.25f}, what, m.texture) * scale;
        if (m.texture >= 0) m.textured_lobes = 1;
        const RGB tr = reflectance(p, "transmittance", RGB{0.25f}, what) * scale;
        m.bsdf.add(Lobe::lambert(r));
        if (!tr.is_black()) m.bsdf.add(Lobe::lambert_transmission(tr));
        m.base_color = r;
        m.c_diffuse = 1.f;
    } else if (type == "coateddiffuse" || type == "coatedconductor") {
        // The layer: pbrt-v4's LayeredBxDF, evaluated by the same random walk (coated.cpp).
        const bool conductor = type == "coatedconductor";
        const std::string coat = conductor ? "interface." : "";
        CoatLayer c;
        c.ior = p.real(coat + "eta", 1.5f);
        if (!(c.ior > 0.f)) fail(t, what + ": eta must be positive");
        c.thickness = float_value(p, "thickness", 0.01f);
        if (!(c.thickness > 0.f)) fail(t, what + ": thickness must be positive");
        c.g = std::clamp(float_value(p, "g", 0.f), -0.999f, 0.999f);
        c.albedo = reflectance(p, "albedo", RGB{0.f}, what);
        const int depth = p.integer("maxdepth", 10), samples = p.integer("nsamples", 1);
        if (depth < 1 || depth > 100 || samples < 1 || samples > 64)
            fail(t, what + ": maxdepth must be in [1, 100] and nsamples in [1, 64]");
        c.max_depth = uint8_t(depth);
        c.samples = uint8_t(samples);
        bool smooth = true;
        c.coat = distribution(smooth, coat);
        c.coat_smooth = smooth;
        if (!conductor) {
            const RGB r = reflectance(p, "reflectance", RGB{0.5f}, what, m.texture);
            if (m.texture >= 0) m.textured_lobes = 1;
            m.bsdf.add(Lobe::coated_diffuse(r, c));
            m.base_color = r;
            m.c_diffuse = 1.f;
        } else {
            Fresnel f = conductor_of("conductor.");
            // Under the coat, the conductor's index is relative to the coat's.
            f.eta *= 1.f / c.ior;
            f.k *= 1.f / c.ior;
            bool base_smooth = true;
            const MicrofacetDistribution d = distribution(base_smooth, "conductor.");
            m.bsdf.add(Lobe::coated_conductor(f, base_smooth, d, c));
        }
    } else if (type == "interface") {
        // No surface: only the boundary of the media its shapes' MediumInterface names.
        m.is_interface = true;
        scene_.mark_volumetric(file(), t.line);
    } else if (type == "mix") {
        const Param* q = p.find("materials");
        if (!q || q->type != "string" || q->strings.size() != 2)
            fail(t, "mix needs \"string materials\" with two named materials");
        const float amount = float_value(p, "amount", 0.5f);
        if (!(amount >= 0.f && amount <= 1.f)) fail(t, "mix amount must be in [0, 1]");
        for (int i = 0; i < 2; ++i) {
            const auto it = named_materials_.find(q->strings[std::size_t(i)]);
            if (it == named_materials_.end())
                fail(t, "unknown named material '" + q->strings[std::size_t(i)] + "'");
            const float w = i == 0 ? 1.f - amount : amount;
            const Material& sub = materials_[it->second];
            if (sub.is_interface) fail(t, "mix: an interface material cannot be mixed");
            if (sub.texture >= 0) {
                if (m.texture >= 0 && m.texture != sub.texture)
                    fail(t, "a mix of two differently textured materials is not supported");
                m.texture = sub.texture;
                m.textured_lobes |= uint8_t(sub.textured_lobes << m.bsdf.size());
            }
            if (sub.normal_map >= 0) {
                // One shading frame for the mixture's lobes.
                if (m.normal_map >= 0 && m.normal_map != sub.normal_map)
                    fail(t, "a mix of two differently normal-mapped materials is not supported");
                m.normal_map = sub.normal_map;
            }
            Bsdf b = sub.bsdf;
            b.scale(w);
            for (int l = 0; l < b.size(); ++l)
                if (!m.bsdf.add(b.lobe(l)))
                    fail(t, "a mix may hold at most " + std::to_string(Bsdf::kMaxLobes) + " lobes");
            m.base_color += materials_[it->second].base_color * w;
        }
        m.c_diffuse = 1.f;
    } else {
        fail(t, "unsupported material '" + type +
                    "' (diffuse, conductor, dielectric, diffusetransmission, coateddiffuse, "
                    "coatedconductor, interface, mix)");
    }
    if (p.has("normalmap")) {
        // A tangent-space normal map, read linearly as pbrt-v4 reads it.
        const std::string rel = p.text("normalmap", "");
        if (rel.empty()) fail(t, what + ": \"string normalmap\" needs a file name");
        Texture nm;
        nm.kind = TextureKind::Image;
        nm.image = image_file(t, rel, true);
        scene_.textures.push_back(nm);
        m.normal_map = int32_t(scene_.textures.size() - 1);
    }
    if (p.has("displacement")) warn(file(), t.line, what + ": 'displacement' ignored");
    warn_unused(p, what);
    count("Material " + type);
    return m;
}

uint32_t Importer::scene_material(const GraphicsState& gs) {
    const auto key = std::make_pair(gs.material, gs.area.id);
    const auto it = scene_materials_.find(key);
    if (it != scene_materials_.end()) return it->second;
    Material m = materials_[gs.material];
    if (gs.area.id >= 0) {
        m.emission = gs.area.radiance;
        m.emission_two_sided = gs.area.two_sided;
    }
    scene_.materials.push_back(m);
    const uint32_t index = uint32_t(scene_.materials.size() - 1);
    scene_materials_[key] = index;
    return index;
}

}  // namespace foton::pbrt
