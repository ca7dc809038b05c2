#include "gltf_scene_parts.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace foton {

namespace {
constexpr double kLumensPerWatt = 683.0;
constexpr const char* kExtensionsRead[] = {
    "KHR_lights_punctual",   "KHR_materials_clearcoat", "KHR_materials_emissive_strength",
    "KHR_materials_ior",     "KHR_materials_specular",  "KHR_materials_transmission",
    "KHR_mesh_quantization", "KHR_texture_transform"};
}  // namespace

bool gltf_extension_read(const std::string& name) {
    for (const char* e : kExtensionsRead)
        if (name == e) return true;
    return false;
}

std::string gltf_extensions_read() {
    std::string out;
    for (const char* e : kExtensionsRead) out += (out.empty() ? "" : ", ") + std::string(e);
    return out;
}

Affine gltf_node_transform(const tinygltf::Node& n) {
    Affine xf;
    if (n.matrix.size() == 16) {
        // Column-major.
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) xf.m[r][c] = float(n.matrix[std::size_t(c * 4 + r)]);
        return xf;
    }
    double t[3] = {0, 0, 0}, q[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1};
    if (n.translation.size() == 3)
        for (int i = 0; i < 3; ++i) t[i] = n.translation[std::size_t(i)];
    if (n.rotation.size() == 4)
        for (int i = 0; i < 4; ++i) q[i] = n.rotation[std::size_t(i)];
    if (n.scale.size() == 3)
        for (int i = 0; i < 3; ++i) s[i] = n.scale[std::size_t(i)];
    const double x = q[0], y = q[1], z = q[2], w = q[3];
    const double R[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                            {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                            {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) xf.m[r][c] = float(R[r][c] * s[c]);
        xf.m[r][3] = float(t[r]);
    }
    return xf;
}

std::optional<ModelView> gltf_camera(const tinygltf::Model& g, int c, const Affine& xf) {
    if (c < 0 || std::size_t(c) >= g.cameras.size())
        throw std::invalid_argument("camera " + std::to_string(c) + " does not exist");
    const tinygltf::Camera& gc = g.cameras[std::size_t(c)];
    ModelView v;
    v.eye = xf.point({0.f, 0.f, 0.f});
    v.target = v.eye + normalize(xf.vector({0.f, 0.f, -1.f}));
    v.up = normalize(xf.vector({0.f, 1.f, 0.f}));
    if (gc.type == "orthographic") {
        // The node's scale does not widen the view: xmag and ymag are the half extents.
        const double xmag = gc.orthographic.xmag, ymag = gc.orthographic.ymag;
        if (!(std::fabs(xmag) > 0.0 && std::fabs(ymag) > 0.0 && std::isfinite(xmag) &&
              std::isfinite(ymag)))
            throw std::invalid_argument("an orthographic camera's xmag and ymag must not be 0");
        v.orthographic = true;
        v.half_height = float(std::fabs(ymag));
        v.aspect = float(std::fabs(xmag / ymag));
        if (!(v.aspect > 0.01f && v.aspect < 100.f))
            throw std::invalid_argument("an orthographic camera's xmag / ymag is out of range");
        return v;
    }
    if (gc.type != "perspective") return std::nullopt;
    const double yfov = gc.perspective.yfov * 180.0 / kPi;
    if (!(yfov > 0.0 && yfov < 180.0))
        throw std::invalid_argument("a camera's yfov must be in (0, pi)");
    v.vertical_fov_degrees = float(yfov);
    if (gc.perspective.aspectRatio > 0.0 && gc.perspective.aspectRatio < 100.0)
        v.aspect = float(gc.perspective.aspectRatio);
    return v;
}

void gltf_light(const tinygltf::Model& g, int l, const Affine& xf, FileLights& out,
                std::vector<std::string>& notes, const std::string& where) {
    if (l < 0 || std::size_t(l) >= g.lights.size())
        throw std::invalid_argument("KHR_lights_punctual light " + std::to_string(l) +
                                    " does not exist");
    const tinygltf::Light& gl = g.lights[std::size_t(l)];
    RGB colour{1.f};
    if (gl.color.size() >= 3)
        colour = RGB{float(gl.color[0]), float(gl.color[1]), float(gl.color[2])};
    const RGB power = colour * float(gl.intensity / kLumensPerWatt);
    if (!(std::min({power.r, power.g, power.b}) >= 0.f) || !std::isfinite(power.max_component()))
        throw std::invalid_argument(
            "a light's colour and intensity must be finite and not "
            "negative");
    if (gl.range > 0.0) notes.push_back(where + ": light range ignored (inverse-square falloff)");
    const Vec3 p = xf.point({0.f, 0.f, 0.f}), d = normalize(xf.vector({0.f, 0.f, -1.f}));
    if (gl.type == "point") {
        out.points.push_back({p, power, 0.f});
    } else if (gl.type == "spot") {
        SpotLight s;
        s.position = p;
        s.direction = d;
        s.intensity = power;
        s.cos_outer = float(std::cos(gl.spot.outerConeAngle));
        s.cos_inner = float(std::cos(gl.spot.innerConeAngle));
        if (!(s.cos_inner >= s.cos_outer))
            throw std::invalid_argument(
                "a spot light's innerConeAngle exceeds its "
                "outerConeAngle");
        out.spots.push_back(s);
    } else if (gl.type == "directional") {
        out.directionals.push_back({d, power});
    } else {
        throw std::invalid_argument("unknown KHR_lights_punctual type '" + gl.type + "'");
    }
}

void gltf_node_extras(const tinygltf::Model& g, const tinygltf::Node& n, const Affine& xf,
                      MeshFile& out, const std::string& where) {
    if (n.camera >= 0) {
        if (out.view)
            out.notes.push_back(where + ": camera " + std::to_string(n.camera) +
                                " ignored (the first camera is the file's view)");
        else if (!(out.view = gltf_camera(g, n.camera, xf)))
            throw std::invalid_argument("camera " + std::to_string(n.camera) +
                                        " has an unknown type");
    }
    if (const auto it = n.extensions.find("KHR_lights_punctual");
        it != n.extensions.end() && it->second.Has("light"))
        gltf_light(g, it->second.Get("light").GetNumberAsInt(), xf, out.lights, out.notes, where);
}

namespace {

int gltf_extension_texture(const tinygltf::Value& v, const char* key, UvMap& uv, FileMaterial& f,
                           std::vector<std::string>& notes, const std::string& where);

// KHR_materials_specular's factors and its strength texture: the dielectric reflection's
// weight and F0 tint (the tint's texture is noted: it would need a per-hit Fresnel).
void gltf_specular(const tinygltf::Value& v, FileMaterial& f, std::vector<std::string>& notes,
                   const std::string& where) {
    if (v.Has("specularFactor")) {
        f.dielectric_weight = float(v.Get("specularFactor").GetNumberAsDouble());
        if (!(f.dielectric_weight >= 0.f && f.dielectric_weight <= 1.f))
            throw std::invalid_argument("specularFactor must be in [0, 1]");
    }
    if (v.Has("specularColorFactor")) {
        const tinygltf::Value& c = v.Get("specularColorFactor");
        if (!c.IsArray() || c.ArrayLen() != 3)
            throw std::invalid_argument("specularColorFactor must be 3 numbers");
        float rgb[3];
        for (int i = 0; i < 3; ++i) {
            rgb[i] = float(c.Get(i).GetNumberAsDouble());
            if (!(rgb[i] >= 0.f && std::isfinite(rgb[i])))
                throw std::invalid_argument("specularColorFactor must be finite, not negative");
        }
        f.dielectric_tint = RGB{rgb[0], rgb[1], rgb[2]};
    }
    f.specular_texture =
        gltf_extension_texture(v, "specularTexture", f.specular_uv, f, notes, where);
    if (v.Has("specularColorTexture"))
        notes.push_back(where + ": KHR_materials_specular specularColorTexture ignored");
}

// An extension's texture reference ({"index", "texCoord", "extensions"}): its texture index
// (-1 when absent) and KHR_texture_transform; its uv set the material's
// (gltf_use_tex_coord).
int gltf_extension_texture(const tinygltf::Value& v, const char* key, UvMap& uv, FileMaterial& f,
                           std::vector<std::string>& notes, const std::string& where) {
    if (!v.Has(key)) return -1;
    const tinygltf::Value& t = v.Get(key);
    if (!t.IsObject() || !t.Has("index") || !t.Get("index").IsInt())
        throw std::invalid_argument(std::string(key) + " needs an integer \"index\"");
    int tex_coord = t.Has("texCoord") ? t.Get("texCoord").GetNumberAsInt() : 0;
    if (t.Has("extensions") && t.Get("extensions").IsObject())
        uv = gltf_uv_map(t.Get("extensions").Get<tinygltf::Value::Object>(), tex_coord);
    uv.set = gltf_use_tex_coord(f, tex_coord, key, notes, where);
    return t.Get("index").GetNumberAsInt();
}

// KHR_materials_clearcoat's factors and textures (its normal texture is noted: the
// material's shading normal stands for it).
void gltf_clearcoat(const tinygltf::Value& v, FileMaterial& f, std::vector<std::string>& notes,
                    const std::string& where) {
    auto factor = [&](const char* key, float& out) {
        if (!v.Has(key)) return;
        out = float(v.Get(key).GetNumberAsDouble());
        if (!(out >= 0.f && out <= 1.f))
            throw std::invalid_argument(std::string(key) + " must be in [0, 1]");
    };
    factor("clearcoatFactor", f.clearcoat);
    factor("clearcoatRoughnessFactor", f.clearcoat_roughness);
    f.clearcoat_texture =
        gltf_extension_texture(v, "clearcoatTexture", f.clearcoat_uv, f, notes, where);
    f.clearcoat_roughness_texture = gltf_extension_texture(
        v, "clearcoatRoughnessTexture", f.clearcoat_roughness_uv, f, notes, where);
    if (v.Has("clearcoatNormalTexture"))
        notes.push_back(where +
                        ": KHR_materials_clearcoat clearcoatNormalTexture ignored (the coat "
                        "takes the material's shading normal)");
}

}  // namespace

void gltf_material_extensions(const tinygltf::Material& gm, FileMaterial& f,
                              std::vector<std::string>& notes, const std::string& where) {
    if (const auto it = gm.extensions.find("KHR_materials_transmission");
        it != gm.extensions.end() && it->second.Has("transmissionFactor")) {
        f.transmission = float(it->second.Get("transmissionFactor").GetNumberAsDouble());
        if (!(f.transmission >= 0.f && f.transmission <= 1.f))
            throw std::invalid_argument("transmissionFactor must be in [0, 1]");
        f.transmission_texture = gltf_extension_texture(it->second, "transmissionTexture",
                                                        f.transmission_uv, f, notes, where);
    }
    f.ior = 1.5f;  // glTF's default
    if (const auto it = gm.extensions.find("KHR_materials_ior");
        it != gm.extensions.end() && it->second.Has("ior")) {
        f.ior = float(it->second.Get("ior").GetNumberAsDouble());
        if (!(f.ior >= 1.f && f.ior < 10.f)) throw std::invalid_argument("ior must be in [1, 10)");
    }
    if (const auto it = gm.extensions.find("KHR_materials_specular"); it != gm.extensions.end())
        gltf_specular(it->second, f, notes, where);
    if (const auto it = gm.extensions.find("KHR_materials_clearcoat"); it != gm.extensions.end())
        gltf_clearcoat(it->second, f, notes, where);
    for (const auto& [ext, value] : gm.extensions)
        if (ext != "KHR_materials_emissive_strength" && ext != "KHR_materials_transmission" &&
            ext != "KHR_materials_ior" && ext != "KHR_materials_specular" &&
            ext != "KHR_materials_clearcoat")
            notes.push_back(where + ": extension " + ext + " ignored");
}

void gltf_alpha_mode(const tinygltf::Material& gm, FileMaterial& f) {
    const std::string& mode = gm.alphaMode;
    if (mode.empty() || mode == "OPAQUE") return;  // the base colour's alpha is ignored
    if (mode != "MASK" && mode != "BLEND")
        throw std::invalid_argument("alphaMode '" + mode + "' (OPAQUE, MASK or BLEND expected)");
    const auto& factor = gm.pbrMetallicRoughness.baseColorFactor;
    f.alpha = factor.size() == 4 ? float(factor[3]) : 1.f;
    if (!(f.alpha >= 0.f && f.alpha <= 1.f))
        throw std::invalid_argument("baseColorFactor's alpha must be in [0, 1]");
    // The base colour texture's alpha channel, when its image has one (add_file_material).
    f.alpha_map = f.diffuse_map;
    if (mode == "MASK") {
        f.alpha_cutoff = float(gm.alphaCutoff);
        if (!(f.alpha_cutoff >= 0.f && f.alpha_cutoff <= 1.f))
            throw std::invalid_argument("alphaCutoff must be in [0, 1]");
    }
    // BLEND: the alpha is the fraction of light the surface stops, which is what the
    // stochastic test (Material::alpha_cutoff < 0) renders in expectation.
}

uint8_t gltf_use_tex_coord(FileMaterial& f, int tex_coord, const std::string& texture,
                           std::vector<std::string>& notes, const std::string& where) {
    if (tex_coord < 0) throw std::invalid_argument(texture + ": texCoord must not be negative");
    if (f.tex_coord < 0) f.tex_coord = tex_coord;
    if (tex_coord == f.tex_coord) return 0;
    if (f.tex_coord2 < 0) f.tex_coord2 = tex_coord;
    if (tex_coord == f.tex_coord2) return 1;
    notes.push_back(where + ": " + texture + " uses TEXCOORD_" + std::to_string(tex_coord) +
                    ", a third uv set in one material; it reads TEXCOORD_" +
                    std::to_string(f.tex_coord) + ", the first texture's");
    return 0;
}

UvMap gltf_uv_map(const std::map<std::string, tinygltf::Value>& extensions, int& tex_coord) {
    UvMap m;
    const auto it = extensions.find("KHR_texture_transform");
    if (it == extensions.end()) return m;
    const tinygltf::Value& t = it->second;
    auto pair = [&](const char* key, float x, float y) {
        if (!t.Has(key)) return std::pair{x, y};
        const tinygltf::Value& a = t.Get(key);
        if (!a.IsArray() || a.ArrayLen() != 2)
            throw std::invalid_argument(std::string("KHR_texture_transform ") + key +
                                        " must be two numbers");
        return std::pair{float(a.Get(0).GetNumberAsDouble()), float(a.Get(1).GetNumberAsDouble())};
    };
    const auto [ox, oy] = pair("offset", 0.f, 0.f);
    const auto [sx, sy] = pair("scale", 1.f, 1.f);
    const float r = t.Has("rotation") ? float(t.Get("rotation").GetNumberAsDouble()) : 0.f;
    if (!std::isfinite(ox + oy + sx + sy + r))
        throw std::invalid_argument("KHR_texture_transform values must be finite");
    if (t.Has("texCoord")) tex_coord = t.Get("texCoord").GetNumberAsInt();
    // glTF: uv' = T R S uv with R = [cos sin; -sin cos], in coordinates whose v runs down;
    // foton's v is 1 - glTF's, on both sides.
    const float c = std::cos(r), s = std::sin(r);
    m.su = c * sx;
    m.suv = -s * sy;
    m.du = s * sy + ox;
    m.svu = s * sx;
    m.sv = c * sy;
    m.dv = 1.f - c * sy - oy;
    return m;
}

TextureImage gltf_decode_image(const tinygltf::Image& im, const std::string& name, bool linear) {
    if (im.width <= 0 || im.height <= 0 || (im.bits != 8 && im.bits != 16) || im.component < 1 ||
        im.component > 4)
        throw std::invalid_argument("could not be decoded (PNG or JPEG of 8 or 16 bits expected)");
    const std::size_t bytes = std::size_t(im.bits / 8);
    const std::size_t texels = std::size_t(im.width) * std::size_t(im.height);
    if (im.image.size() != texels * std::size_t(im.component) * bytes)
        throw std::invalid_argument("decoded size does not match its resolution");
    TextureImage out;
    out.path = name;
    out.width = im.width;
    out.height = im.height;
    out.texels.resize(texels);
    const float unit = im.bits == 8 ? 255.f : 65535.f;
    for (std::size_t i = 0; i < texels; ++i) {
        float c[4] = {0.f, 0.f, 0.f, 0.f};
        for (int k = 0; k < std::min(im.component, 3); ++k) {
            const std::size_t o = (i * std::size_t(im.component) + std::size_t(k)) * bytes;
            uint16_t v = im.image[o];
            if (bytes == 2) std::memcpy(&v, &im.image[o], 2);
            c[k] = linear ? float(v) / unit : srgb_to_linear(float(v) / unit);
        }
        // Grey (and grey + alpha) images repeat their one channel.
        if (im.component < 3) c[1] = c[2] = c[0];
        out.texels[i] = RGB{c[0], c[1], c[2]};
        if (im.component == 2 || im.component == 4) {
            // Alpha is linear; kept for alphaMode MASK and BLEND.
            const std::size_t o =
                (i * std::size_t(im.component) + std::size_t(im.component - 1)) * bytes;
            uint16_t v = im.image[o];
            if (bytes == 2) std::memcpy(&v, &im.image[o], 2);
            if (out.alpha.empty()) out.alpha.assign(texels, 1.f);
            out.alpha[i] = float(v) / unit;
        }
    }
    bool opaque = true;
    for (float a : out.alpha) opaque = opaque && a >= 1.f;
    if (opaque) out.alpha.clear();
    return out;
}

TextureWrap gltf_wrap(int mode) {
    switch (mode) {
        case TINYGLTF_TEXTURE_WRAP_REPEAT:
            return TextureWrap::Repeat;
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
            return TextureWrap::Clamp;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
            return TextureWrap::Mirror;
    }
    throw std::invalid_argument("wrap mode " + std::to_string(mode) +
                                " is not one of glTF's (10497, 33071, 33648)");
}

std::vector<uint32_t> gltf_triangle_list(std::vector<uint32_t> indices, int mode) {
    if (mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) return indices;
    std::vector<uint32_t> out;
    const std::size_t n = indices.size();
    if (n < 3) return out;
    out.reserve(3 * (n - 2));
    for (std::size_t i = 0; i + 2 < n; ++i) {
        if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
            // Every other triangle of a strip turns the other way: swap to keep the winding.
            const std::size_t odd = i % 2;
            out.insert(out.end(), {indices[i], indices[i + 1 + odd], indices[i + 2 - odd]});
        } else {
            out.insert(out.end(), {indices[i + 1], indices[i + 2], indices[0]});
        }
    }
    return out;
}

std::string gltf_unread_image_reason(const std::string& load_warnings, const std::string& uri) {
    std::size_t at = 0;
    while (at < load_warnings.size()) {
        std::size_t end = load_warnings.find('\n', at);
        if (end == std::string::npos) end = load_warnings.size();
        const std::string line = load_warnings.substr(at, end - at);
        if (line.find(uri) != std::string::npos &&
            (line.rfind("File read error", 0) == 0 || line.rfind("File not found", 0) == 0))
            return "'" + uri + "' could not be read (" + line + ")";
        at = end + 1;
    }
    return "'" + uri + "' could not be read";
}

}  // namespace foton
