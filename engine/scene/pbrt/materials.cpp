// Material, MakeNamedMaterial and Texture: pbrt-v4's materials as foton BSDFs.
#include <cmath>
#include <vector>

#include "engine/core/input_file.h"
#include "engine/scene/metals.h"
#include "importer.h"

namespace foton::pbrt {

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
    // specular. A roughness texture makes the lobe rough everywhere and is read at each hit
    // (Material::float_params): `pending` holds it until add_lobe knows the lobe's index.
    std::vector<Material::FloatParam> pending;
    auto distribution = [&](bool& smooth, const std::string& prefix = "", bool coat = false) {
        const bool remap = p.boolean("remaproughness", true);
        int32_t tu = -1, tv = -1;
        float u = float_value(p, prefix + "roughness", 0.f, tu), v = u;
        tv = tu;
        if (p.has(prefix + "uroughness")) u = float_value(p, prefix + "uroughness", u, tu);
        if (p.has(prefix + "vroughness")) v = float_value(p, prefix + "vroughness", v, tv);
        // A textured axis' alpha until the first hit sets it.
        const float ax = tu >= 0 ? 0.5f : alpha_of(u, remap),
                    ay = tv >= 0 ? 0.5f : alpha_of(v, remap);
        smooth = tu < 0 && tv < 0 && std::max(ax, ay) < 1e-3f;
        if (!smooth && std::max(ax, ay) > 2.f) fail(t, what + ": roughness gives alpha above 2");
        if (tu >= 0)
            pending.push_back({tu, 0, coat ? LobeParam::CoatAlphaX : LobeParam::AlphaX,
                               remap ? Material::Remap::Sqrt : Material::Remap::None});
        if (tv >= 0)
            pending.push_back({tv, 0, coat ? LobeParam::CoatAlphaY : LobeParam::AlphaY,
                               remap ? Material::Remap::Sqrt : Material::Remap::None});
        return MicrofacetDistribution::trowbridge_reitz(std::clamp(ax, 1e-4f, 2.f),
                                                        std::clamp(ay, 1e-4f, 2.f));
    };
    auto add_lobe = [&](const Lobe& lobe) {
        m.bsdf.add(lobe);
        for (Material::FloatParam fp : pending) {
            fp.lobe = uint8_t(m.bsdf.size() - 1);
            if (!m.add_float_param(fp)) fail(t, what + ": too many roughness textures");
        }
        pending.clear();
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
            add_lobe(Lobe::mirror(RGB{1.f}, f));
        else
            add_lobe(Lobe::microfacet(RGB{1.f}, d, f));
    } else if (type == "dielectric" || type == "thindielectric") {
        float eta = 1.5f;
        Dispersion glass;
        if (const Param* q = p.find("eta")) {
            if (q->type == "float") {
                eta = p.real("eta", 1.5f);
            } else if (q->type == "spectrum" && q->strings.size() == 1 &&
                       named_glass(q->strings[0], glass)) {
                // A named glass disperses (spectral volpath); elsewhere its d-line index.
                eta = p.color("eta", false)->g;
                if (glass_line_ == 0) {
                    glass_file_ = file();
                    glass_line_ = q->line;
                    glass_name_ = q->strings[0];
                }
                if (type == "thindielectric") {
                    glass = Dispersion{};
                    warn(file(), q->line,
                         what + ": a thin pane's dispersion is not rendered (its d-line index)");
                }
            } else {
                const auto c = p.color("eta", false);
                eta = c->g;
                warn(file(), q->line, what + ": a spectral eta is rendered without dispersion");
            }
        }
        if (!(eta > 0.f)) fail(t, what + ": eta must be positive");
        m.ior = eta;
        if (type == "thindielectric") {
            // A pane: smooth (pbrt-v4's has no roughness), light keeps its direction.
            add_lobe(Lobe::thin_dielectric(eta, RGB{1.f}, RGB{1.f}));
        } else {
            bool smooth = true;
            const MicrofacetDistribution d = distribution(smooth);
            Lobe l = smooth ? Lobe::dielectric(eta, RGB{1.f}, RGB{1.f})
                            : Lobe::rough_dielectric(eta, d, RGB{1.f}, RGB{1.f});
            l.dispersion = glass;
            add_lobe(l);
        }
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
        c.coat = distribution(smooth, coat, true);
        c.coat_smooth = smooth;
        if (!conductor) {
            const RGB r = reflectance(p, "reflectance", RGB{0.5f}, what, m.texture);
            if (m.texture >= 0) m.textured_lobes = 1;
            add_lobe(Lobe::coated_diffuse(r, c));
            m.base_color = r;
            m.c_diffuse = 1.f;
        } else {
            Fresnel f = conductor_of("conductor.");
            // Under the coat, the conductor's index is relative to the coat's.
            f.eta *= 1.f / c.ior;
            f.k *= 1.f / c.ior;
            bool base_smooth = true;
            const MicrofacetDistribution d = distribution(base_smooth, "conductor.");
            add_lobe(Lobe::coated_conductor(f, base_smooth, d, c));
        }
    } else if (type == "subsurface") {
        // A dielectric boundary (smooth or rough) over the scattering medium (subsurface.cpp).
        subsurface_material(t, p, m, what);
        bool smooth = true;
        const MicrofacetDistribution d = distribution(smooth);
        add_lobe(smooth ? Lobe::dielectric(m.ior, RGB{1.f}, RGB{1.f})
                        : Lobe::rough_dielectric(m.ior, d, RGB{1.f}, RGB{1.f}));
    } else if (type == "interface") {
        // No surface: only the boundary of the media its shapes' MediumInterface names.
        m.is_interface = true;
        scene_.mark_volumetric(file(), t.line);
    } else if (type == "mix") {
        const Param* q = p.find("materials");
        if (!q || q->type != "string" || q->strings.size() != 2)
            fail(t, "mix needs \"string materials\" with two named materials");
        // A texture amount weighs the two materials' lobes per hit (1 - v and v: pbrt-v4
        // picks one of them with those probabilities, the same expected image).
        int32_t amount_texture = -1;
        const float amount = float_value(p, "amount", 0.5f, amount_texture);
        if (!(amount >= 0.f && amount <= 1.f)) fail(t, "mix amount must be in [0, 1]");
        for (int i = 0; i < 2; ++i) {
            const auto it = named_materials_.find(q->strings[std::size_t(i)]);
            if (it == named_materials_.end())
                fail(t, "unknown named material '" + q->strings[std::size_t(i)] + "'");
            const float w = amount_texture >= 0 ? 1.f : i == 0 ? 1.f - amount : amount;
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
            if (sub.bump >= 0) {
                if (m.bump >= 0 && m.bump != sub.bump)
                    fail(t, "a mix of two differently bump-mapped materials is not supported");
                m.bump = sub.bump;
            }
            for (int f = 0; f < sub.num_float_params; ++f) {
                Material::FloatParam fp = sub.float_params[std::size_t(f)];
                fp.lobe = uint8_t(fp.lobe + m.bsdf.size());
                if (!m.add_float_param(fp)) fail(t, "mix: too many roughness textures");
            }
            Bsdf b = sub.bsdf;
            b.scale(w);
            for (int l = 0; l < b.size(); ++l) {
                if (!m.bsdf.add(b.lobe(l)))
                    fail(t, "a mix may hold at most " + std::to_string(Bsdf::kMaxLobes) + " lobes");
                const Material::FloatParam share{
                    amount_texture, uint8_t(m.bsdf.size() - 1),
                    i == 0 ? LobeParam::WeightComplement : LobeParam::Weight, Material::Remap::None,
                    0};
                if (amount_texture >= 0 && !m.add_float_param(share))
                    fail(t, "mix: too many textured parameters");
            }
            // (With a texture amount, the base colour takes the two halves.)
            m.base_color += materials_[it->second].base_color * (amount_texture >= 0 ? 0.5f : w);
        }
        m.c_diffuse = 1.f;
    } else if (type == "measured") {
        // A measured BRDF (measured_brdf.h), each file read once.
        const std::string rel = p.text("filename", "");
        if (rel.empty()) fail(t, what + " needs a \"string filename\" (a .bsdf file)");
        const std::string path = input_path(t, what + " file", rel, kMaxMeshFileBytes);
        auto& brdf = measured_files_[path];
        if (!brdf) {
            brdf = load_measured_brdf(path);
            scene_.measured_brdfs.push_back(brdf);
        }
        m.bsdf.add(Lobe::measured_brdf(brdf.get()));
        m.base_color = RGB{0.5f};
    } else if (type == "hair") {
        // Chiang et al.'s fibre (hair.cpp); its absorption from sigma_a, else from a
        // reflectance, else from melanin (pbrt-v4's order and defaults: eumelanin 1.3).
        HairFiber h;
        h.eta = float_value(p, "eta", 1.55f);
        h.beta_m = std::max(1e-2f, float_value(p, "beta_m", 0.3f));
        h.beta_n = std::max(1e-2f, float_value(p, "beta_n", 0.3f));
        h.alpha_degrees = float_value(p, "alpha", 2.f);
        if (!(h.eta > 0.f) || !(h.beta_m <= 1.f) || !(h.beta_n <= 1.f) ||
            !std::isfinite(h.alpha_degrees))
            fail(t, what + ": eta must be positive, beta_m and beta_n in [0, 1]");
        const bool melanin = p.has("eumelanin") || p.has("pheomelanin");
        auto ignored = [&](bool given, const char* name, const char* why) {
            if (given) warn(file(), t.line, what + ": " + name + " ignored (" + why + " given)");
        };
        if (p.has("sigma_a")) {
            if (texture_ref(p, "sigma_a", false))
                fail(t, what + ": a sigma_a texture is not supported (an rgb value is)");
            h.sigma_a = *p.color("sigma_a", false);
            ignored(p.has("reflectance"), "reflectance", "sigma_a");
            ignored(melanin, "eumelanin and pheomelanin", "sigma_a");
        } else if (p.has("reflectance") || p.has("color")) {
            // pbrt-v4 reads "color" when there is no "reflectance" (pbrt-v3's name).
            const char* key = p.has("reflectance") ? "reflectance" : "color";
            m.base_color = reflectance(p, key, RGB{0.5f}, what);
            h.sigma_a = hair_sigma_a_from_reflectance(m.base_color, h.beta_n);
            ignored(melanin, "eumelanin and pheomelanin", key);
            ignored(p.has("color") && p.has("reflectance"), "color", "reflectance");
        } else {
            h.sigma_a = hair_sigma_a_from_melanin(
                std::max(0.f, float_value(p, "eumelanin", melanin ? 0.f : 1.3f)),
                std::max(0.f, float_value(p, "pheomelanin", 0.f)));
        }
        if (!(h.sigma_a.r >= 0.f && h.sigma_a.g >= 0.f && h.sigma_a.b >= 0.f))
            fail(t, what + ": sigma_a must not be negative");
        if (m.base_color.is_black())
            m.base_color =
                RGB{std::exp(-h.sigma_a.r), std::exp(-h.sigma_a.g), std::exp(-h.sigma_a.b)};
        m.bsdf.add(Lobe::hair_fiber(h));
    } else {
        fail(t, "unsupported material '" + type +
                    "' (diffuse, conductor, dielectric, thindielectric, diffusetransmission, "
                    "coateddiffuse, "
                    "coatedconductor, hair, measured, interface, mix)");
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
    if (p.has("displacement")) {
        // Bump mapping by a float texture (a constant one too: it moves a curved surface's
        // shading normal as pbrt-v4's BumpMap does).
        int32_t bump = -1;
        const float d = float_value(p, "displacement", 0.f, bump);
        if (bump < 0 && d != 0.f) {
            Texture c;
            c.value = RGB{d};
            scene_.textures.push_back(c);
            bump = int32_t(scene_.textures.size() - 1);
        }
        if (bump >= 0) m.bump = bump;
    }
    warn_unused(p, what);
    count("Material " + type);
    return m;
}

uint32_t Importer::scene_material(const GraphicsState& gs) {
    const auto key = std::make_tuple(gs.material, gs.area.id, shape_alpha_, shape_alpha_texture_);
    const auto it = scene_materials_.find(key);
    if (it != scene_materials_.end()) return it->second;
    Material m = materials_[gs.material];
    if (gs.area.id >= 0) {
        m.emission = gs.area.radiance;
        m.emission_two_sided = gs.area.two_sided;
        m.emission_texture = gs.area.texture;
    }
    m.alpha = shape_alpha_;
    m.alpha_texture = shape_alpha_texture_;
    scene_.materials.push_back(m);
    const uint32_t index = uint32_t(scene_.materials.size() - 1);
    scene_materials_[key] = index;
    return index;
}

}  // namespace foton::pbrt
