// Texture and the texture-valued parameters of materials: pbrt-v4's constant, scale,
// imagemap and checkerboard textures, spectrum- and float-valued.
#include <algorithm>

#include "engine/core/input_file.h"
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

namespace {

// How deep a mix or product texture nests them (operands are copies: a chain grows the copy).
int mix_depth(const Texture& tx) {
    int d = 0;
    for (const Texture& o : tx.operands) d = std::max(d, mix_depth(o));
    return tx.operands.empty() ? d : d + 1;
}

}  // namespace

float Importer::float_value(const ParamList& p, const std::string& name, float fallback) {
    const TextureDesc* tx = texture_ref(p, name, true);
    if (tx && tx->scene_texture >= 0)
        throw InputError(p.file, p.find(name)->line,
                         "a varying texture on '" + name + "' is not supported");
    return tx ? tx->value.r : p.real(name, fallback);
}

float Importer::float_value(const ParamList& p, const std::string& name, float fallback,
                            int32_t& texture) {
    const TextureDesc* tx = texture_ref(p, name, true);
    texture = tx ? tx->scene_texture : -1;
    return texture >= 0 ? 0.f : float_value(p, name, fallback);
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
        // A constant factor folds into the texture it scales, varying or not; a varying
        // factor makes a product texture.
        const TextureDesc* varying = texture_ref(p, "scale", true);
        if (varying && varying->scene_texture >= 0) {
            product_texture(t, p, tex);
            textures_[name] = tex;
            warn_unused(p, "Texture \"" + name + "\"");
            count("Texture " + type);
            return;
        }
        const float factor = float_value(p, "scale", 1.f);
        const TextureDesc* inner = texture_ref(p, "tex", tex.is_float);
        if (inner && inner->scene_texture >= 0) {
            Texture st = scene_.textures[std::size_t(inner->scene_texture)];
            if (st.invert) fail(t, "a scale of an inverted texture is not supported");
            st.scale *= factor;
            scene_.textures.push_back(st);
            tex.scene_texture = int32_t(scene_.textures.size() - 1);
        } else {
            tex.value = value("tex", RGB{1.f}) * factor;
        }
    } else if (type == "imagemap" || type == "checkerboard") {
        Texture st;
        if (type == "imagemap") {
            st.kind = TextureKind::Image;
            st.image = image_texture(t, p, st);
            st.scale = RGB{p.real("scale", 1.f)};
            st.invert = p.boolean("invert", false);
        } else {
            if (p.integer("dimension", 2) != 2) fail(t, "only 2D checkerboards are supported");
            st.kind = TextureKind::Checkerboard;
            st.value = value("tex1", RGB{1.f});
            st.other = value("tex2", RGB{0.f});
        }
        texture_mapping(t, p, st);
        scene_.textures.push_back(st);
        tex.scene_texture = int32_t(scene_.textures.size() - 1);
    } else if (type == "mix") {
        mix_texture(t, p, tex);
    } else if (type == "directionmix") {
        direction_mix_texture(t, p, tex);
    } else if (type == "fbm" || type == "wrinkled" || type == "windy" || type == "marble") {
        noise_texture(t, type, p, tex);
    } else if (type == "bilerp" || type == "dots") {
        // Both read (s, t) through the 2D mapping; their operands are values or textures.
        bool varies = true;
        Texture st;
        if (type == "bilerp") {
            st.kind = TextureKind::Bilerp;
            st.operands = {texture_operand(p, "v00", tex.is_float, 0.f, varies),
                           texture_operand(p, "v01", tex.is_float, 1.f, varies),
                           texture_operand(p, "v10", tex.is_float, 0.f, varies),
                           texture_operand(p, "v11", tex.is_float, 1.f, varies)};
        } else {
            st.kind = TextureKind::Dots;
            st.operands = {texture_operand(p, "inside", tex.is_float, 1.f, varies),
                           texture_operand(p, "outside", tex.is_float, 0.f, varies)};
        }
        texture_mapping(t, p, st);
        tex.scene_texture = add_texture(t, std::move(st));
    } else {
        fail(t, "texture type '" + type +
                    "' is not supported (constant, scale, mix, directionmix, fbm, wrinkled, "
                    "windy, marble, bilerp, dots, imagemap and checkerboard)");
    }
    textures_[name] = tex;
    warn_unused(p, "Texture \"" + name + "\"");
    count("Texture " + type);
}

Texture Importer::texture_operand(const ParamList& p, const std::string& key, bool is_float,
                                  float fallback, bool& varies) {
    Texture o;
    if (const TextureDesc* d = texture_ref(p, key, is_float)) {
        if (d->scene_texture >= 0) {
            varies = true;
            return scene_.textures[std::size_t(d->scene_texture)];
        }
        o.value = d->value;
    } else if (is_float) {
        o.value = RGB{p.real(key, fallback)};
    } else {
        const auto c = p.color(key, false);
        o.value = c ? *c : RGB{fallback};
    }
    return o;
}

int32_t Importer::add_texture(const Token& t, Texture tx) {
    if (mix_depth(tx) > 8) fail(t, "textures made of textures nest deeper than 8");
    scene_.textures.push_back(std::move(tx));
    return int32_t(scene_.textures.size() - 1);
}

void Importer::product_texture(const Token& t, const ParamList& p, TextureDesc& tex) {
    bool varies = true;
    Texture product;
    product.kind = TextureKind::Product;
    product.operands = {texture_operand(p, "tex", tex.is_float, 1.f, varies),
                        texture_operand(p, "scale", true, 1.f, varies)};
    tex.scene_texture = add_texture(t, std::move(product));
}

void Importer::texture_mapping(const Token& t, const ParamList& p, Texture& st) {
    const std::string mapping = p.text("mapping", "uv");
    st.uv.du = p.real("udelta", 0.f);
    st.uv.dv = p.real("vdelta", 0.f);
    if (mapping == "uv") {
        st.uv.su = p.real("uscale", 1.f);
        st.uv.sv = p.real("vscale", 1.f);
        return;
    }
    // By position: the point in the space the texture was declared in (pbrt-v4 ignores
    // uscale and vscale there; planar takes udelta and vdelta as its offsets).
    if (std::fabs(gs_.ctm.determinant()) < 1e-12f)
        fail(t, "a texture's transform must be invertible for its " + mapping + " mapping");
    st.to_texture = gs_.ctm.inverse();
    if (mapping == "spherical") {
        st.mapping = TextureMapping::Spherical;
    } else if (mapping == "cylindrical") {
        st.mapping = TextureMapping::Cylindrical;
    } else if (mapping == "planar") {
        st.mapping = TextureMapping::Planar;
        auto vec = [&](const std::string& key, Vec3 fallback) {
            const Param* q = p.find(key);
            if (!q) return fallback;
            if (q->numbers.size() != 3) fail(t, "planar mapping: " + key + " needs 3 numbers");
            return Vec3{float(q->numbers[0]), float(q->numbers[1]), float(q->numbers[2])};
        };
        st.plane_s = vec("v1", {1.f, 0.f, 0.f});
        st.plane_t = vec("v2", {0.f, 1.f, 0.f});
    } else {
        fail(t, "texture mapping '" + mapping +
                    "' is not supported (uv, spherical, cylindrical, planar)");
    }
}

void Importer::noise_texture(const Token& t, const std::string& type, const ParamList& p,
                             TextureDesc& tex) {
    const bool marble = type == "marble";
    if (tex.is_float == marble)
        fail(t, "'" + type + "' is a " + (marble ? "spectrum" : "float") + " texture in pbrt-v4");
    Texture st;
    st.kind = TextureKind::Noise;
    st.noise = type == "fbm"        ? NoiseKind::FBm
               : type == "wrinkled" ? NoiseKind::Wrinkled
               : marble             ? NoiseKind::Marble
                                    : NoiseKind::Windy;
    if (marble) {
        st.noise_scale = p.real("scale", 1.f);
        st.variation = p.real("variation", 0.2f);
        if (!std::isfinite(st.noise_scale) || !std::isfinite(st.variation))
            fail(t, "marble: scale and variation must be finite");
    }
    if (st.noise != NoiseKind::Windy) {
        st.octaves = p.integer("octaves", 8);
        st.omega = p.real("roughness", 0.5f);
        if (st.octaves < 1 || st.octaves > 32 || !(st.omega >= 0.f && st.omega <= 1.f))
            fail(t, type + ": octaves must be in [1, 32] and roughness in [0, 1]");
    }
    // Read at the point in the space the texture was declared in.
    if (std::fabs(gs_.ctm.determinant()) < 1e-12f)
        fail(t, type + ": the texture's transform must be invertible");
    st.to_texture = gs_.ctm.inverse();
    tex.scene_texture = add_texture(t, std::move(st));
}

void Importer::direction_mix_texture(const Token& t, const ParamList& p, TextureDesc& tex) {
    bool varies = false;
    Texture mix;
    mix.kind = TextureKind::DirectionMix;
    mix.operands = {texture_operand(p, "tex1", tex.is_float, 0.f, varies),
                    texture_operand(p, "tex2", tex.is_float, 1.f, varies)};
    Vec3 dir{0.f, 1.f, 0.f};  // pbrt-v4's default
    if (const Param* q = p.find("dir")) {
        if (q->numbers.size() != 3) fail(t, "directionmix: dir needs 3 numbers");
        dir = {float(q->numbers[0]), float(q->numbers[1]), float(q->numbers[2])};
    }
    // Declared in the texture's space, used in world space.
    dir = gs_.ctm.vector(dir);
    if (!(length(dir) > 0.f)) fail(t, "directionmix: dir must not be zero");
    mix.mix_dir = normalize(dir);
    tex.scene_texture = add_texture(t, std::move(mix));
}

void Importer::mix_texture(const Token& t, const ParamList& p, TextureDesc& tex) {
    // pbrt-v4's defaults: tex1 0, tex2 1, amount 0.5.
    bool varies = false;
    Texture mix;
    mix.kind = TextureKind::Mix;
    mix.operands = {texture_operand(p, "tex1", tex.is_float, 0.f, varies),
                    texture_operand(p, "tex2", tex.is_float, 1.f, varies),
                    texture_operand(p, "amount", true, 0.5f, varies)};
    if (!varies) {
        // Constants: the mixture is a constant.
        const float a = mix.operands[2].value.r;
        tex.value = mix.operands[0].value * (1.f - a) + mix.operands[1].value * a;
        return;
    }
    tex.scene_texture = add_texture(t, std::move(mix));
}

uint32_t Importer::image_texture(const Token& t, const ParamList& p, Texture& st) {
    const std::string rel = p.text("filename", "");
    if (rel.empty()) fail(t, "imagemap needs \"string filename\"");
    // pbrt-v4's wrap modes but its octahedral sphere (for environment maps, not surfaces).
    const std::string wrap_name = p.text("wrap", "repeat");
    TextureWrap wrap = TextureWrap::Repeat;
    if (wrap_name == "mirror" || !parse_texture_wrap(wrap_name, wrap))
        fail(t, "texture wrap '" + wrap_name + "' is not supported (repeat, clamp, black)");
    // pbrt-v4's filters: bilinear (its default), point, trilinear MIP-mapping and EWA.
    const std::string filter = p.text("filter", "bilinear");
    if (!parse_texture_filter(filter, st.filter))
        fail(t, "texture filter '" + filter + "' (bilinear, point, trilinear, ewa)");
    st.max_anisotropy = p.real("maxanisotropy", 8.f);
    if (!(st.max_anisotropy >= 1.f)) fail(t, "maxanisotropy must be at least 1");
    const std::string enc = p.text("encoding", "sRGB");
    if (enc != "sRGB" && enc != "linear") fail(t, "texture encoding '" + enc + "' (sRGB, linear)");
    const uint32_t image = image_file(t, rel, enc == "linear", wrap);
    TextureImage& img = scene_.texture_images[image];
    if (st.mip_mapped() && img.mip.empty()) img.build_mip();
    scene_.mip_mapped |= st.mip_mapped();
    return image;
}

uint32_t Importer::image_file(const Token& t, const std::string& rel, bool linear,
                              TextureWrap wrap) {
    // An image read under two wrap modes is two images (the mode is the image's).
    const std::string key = rel + (linear ? "#linear" : "") + "#wrap" + std::to_string(int(wrap));
    if (const auto it = images_.find(key); it != images_.end()) return it->second;
    const std::string path = input_path(t, "texture", rel, kMaxMeshFileBytes);
    try {
        scene_.texture_images.push_back(load_texture_image(path, linear));
    } catch (const InputError& e) {
        fail(t, std::string("texture '") + rel + "': " + e.what());
    }
    scene_.texture_images.back().wrap_s = scene_.texture_images.back().wrap_t = wrap;
    return images_[key] = uint32_t(scene_.texture_images.size() - 1);
}

}  // namespace foton::pbrt
