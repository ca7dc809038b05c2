// A material's texture elements: <texture> on the diffuse reflectance, <normal_map>, <bump>
// and <roughness_map>, and the texture reader they share.
#include <filesystem>

#include "loader.h"

namespace foton::xml {

void Loader::material_texture(const pugi::xml_node& n, Material& m) {
    const pugi::xml_node tx = n.child("texture");
    if (!tx) return;
    // The diffuse reflectance's texture: the Lambert or Oren-Nayar lobe (the first one the
    // diffuse types add) and the base colour are multiplied by it.
    const std::string type = n.attribute("type").value();
    const bool diffuse = type == "matte" || type == "phong" || type == "reflective" ||
                         type == "lambert" || type == "oren_nayar" || type == "coated_diffuse";
    if (!diffuse)
        fail(tx,
             "<texture> multiplies a diffuse reflectance: matte, phong, reflective, "
             "lambert, oren_nayar or coated_diffuse (or put it on a mix's component)");
    const LobeType first = m.bsdf.empty() ? LobeType::Mirror : m.bsdf.lobe(0).type;
    if (first != LobeType::Lambert && first != LobeType::OrenNayar && first != LobeType::Coated)
        fail(tx, "<texture> on a material without diffuse reflection (c_diffuse 0)");
    m.texture = parse_texture(tx);
    m.textured_lobes = 1;
}

// <normal_map src="..."/>: a tangent-space normal map (read linearly unless encoding says).
void Loader::material_normal_map(const pugi::xml_node& n, Material& m) {
    const pugi::xml_node nm = n.child("normal_map");
    if (!nm) return;
    if (nm.attribute("type") && std::string_view(nm.attribute("type").value()) != "image")
        fail(nm, "a normal map is an image (<normal_map src=\"...\"/>)");
    m.normal_map = parse_texture(nm, true);
}

// <bump src="..." scale="..."/>: bump mapping by a float texture (the mean of an image's
// channels, read linearly unless encoding says; a checkerboard's mean), of height `scale`
// in scene units.
void Loader::material_bump(const pugi::xml_node& n, Material& m) {
    const pugi::xml_node b = n.child("bump");
    if (!b) return;
    if (!b.attribute("scale"))
        fail(b, "<bump> needs attribute 'scale' (its height in scene units)");
    m.bump = parse_texture(b, true, true);
}

// <roughness_map src="..."/>: the rough lobes' microfacet alpha read from a float texture at
// each hit (values as the material's roughness attribute holds them); the material must be
// rough (a roughness above 0) with a Beckmann or GGX distribution, or a rough coat.
void Loader::material_roughness_map(const pugi::xml_node& n, Material& m) {
    const pugi::xml_node r = n.child("roughness_map");
    if (!r) return;
    const int32_t tex = parse_texture(r, true, true);
    bool any = false;
    auto add = [&](int lobe, LobeParam target) {
        if (!m.add_float_param({tex, uint8_t(lobe), target, Material::Remap::None}))
            fail(r, "too many roughness maps in one material");
        any = true;
    };
    for (int i = 0; i < m.bsdf.size(); ++i) {
        const Lobe& l = m.bsdf.lobe(i);
        const MicrofacetKind k = l.dist.kind;
        if (l.type == LobeType::Coated) {
            if (!l.coat.coat_smooth) {
                add(i, LobeParam::CoatAlphaX);
                add(i, LobeParam::CoatAlphaY);
            }
        } else if ((l.type == LobeType::Microfacet || l.type == LobeType::RoughDielectric) &&
                   (k == MicrofacetKind::Beckmann || k == MicrofacetKind::TrowbridgeReitz)) {
            add(i, LobeParam::AlphaX);
            if (k == MicrofacetKind::TrowbridgeReitz) add(i, LobeParam::AlphaY);
        }
    }
    if (!any)
        fail(r,
             "<roughness_map> needs a rough lobe: a roughness above 0 with distribution beckmann "
             "or ggx, or a rough coat");
}

// <texture src="image" .../> or <texture type="checkerboard">: into Scene::textures.
int32_t Loader::parse_texture(const pugi::xml_node& tx, bool linear_default, bool amplitude) {
    const std::string kind = tx.attribute("type") ? tx.attribute("type").value() : "image";
    Texture t;
    if (amplitude) t.scale = RGB{number(tx, "scale", 1.f)};

    t.uv.su = number(tx, "scale_u", 1.f);
    t.uv.sv = number(tx, "scale_v", 1.f);
    t.uv.du = number(tx, "offset_u", 0.f);
    t.uv.dv = number(tx, "offset_v", 0.f);
    if (kind == "image") {
        if (amplitude)
            check(tx,
                  {"type", "src", "encoding", "scale_u", "scale_v", "offset_u", "offset_v", "scale",
                   "filter"},
                  {});
        else
            check(
                tx,
                {"type", "src", "encoding", "scale_u", "scale_v", "offset_u", "offset_v", "filter"},
                {});
        const std::string src = tx.attribute("src").value();
        if (src.empty()) fail(tx, "<texture> needs attribute 'src' (or type=\"checkerboard\")");
        const std::string enc = tx.attribute("encoding") ? tx.attribute("encoding").value()
                                : linear_default         ? "linear"
                                                         : "srgb";
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
        // filter: bilinear (default), point, trilinear (MIP-mapped by the footprint of a pixel
        // at the hit) or ewa (an elliptical average over that footprint).
        const std::string filter =
            tx.attribute("filter") ? tx.attribute("filter").value() : "bilinear";
        if (!parse_texture_filter(filter, t.filter))
            fail(tx, "unknown texture filter '" + filter + "' (bilinear, point, trilinear, ewa)");
        if (t.mip_mapped() && scene_.texture_images[t.image].mip.empty())
            scene_.texture_images[t.image].build_mip();
        scene_.mip_mapped |= t.mip_mapped();
    } else if (kind == "checkerboard") {
        if (amplitude)
            check(tx, {"type", "scale_u", "scale_v", "offset_u", "offset_v", "scale"},
                  {"even", "odd"});
        else
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
