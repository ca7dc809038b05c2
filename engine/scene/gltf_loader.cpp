// glTF 2.0 through tinygltf (Debian's libtinygltf-dev): the JSON and its buffers and images
// are parsed by the library; every index, offset and stride it hands over is checked before use
// (here and in gltf_accessors.cpp), so a malformed file is an InputError, never a read out of
// bounds.
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "engine/core/error.h"
#include "engine/core/input_file.h"
#include "gltf_accessors.h"
#include "gltf_inputs.h"
#include "gltf_scene_parts.h"
#include "mesh_file.h"

namespace foton {

namespace {

class GltfReader {
  public:
    // `load_warnings`: tinygltf's, which say why an external image could not be read.
    GltfReader(const tinygltf::Model& model, std::string path, std::string load_warnings)
        : g_(model),
          path_(std::move(path)),
          load_warnings_(std::move(load_warnings)),
          accessors_(model, path_,
                     std::count(model.extensionsUsed.begin(), model.extensionsUsed.end(),
                                "KHR_mesh_quantization") > 0) {}

    [[noreturn]] void fail(const std::string& where, const std::string& what) const {
        throw InputError(path_, 0, where + ": " + what);
    }
    void note(const std::string& what) { out_.notes.push_back(path_ + ": " + what); }

    std::vector<float> floats(int a, int n, const std::string& where) const {
        return accessors_.floats(a, n, where);
    }
    std::vector<uint32_t> indices(int a, const std::string& where) const {
        return accessors_.indices(a, where);
    }

    void primitive(const tinygltf::Primitive& p, const Affine& xf, const std::string& where) {
        // Points and lines have no area to render; strips and fans become triangle lists.
        if (p.mode >= 0 && p.mode < TINYGLTF_MODE_TRIANGLES) {
            note(where + ": primitive mode " + std::to_string(p.mode) +
                 " (points or lines) left out: only surfaces are rendered");
            return;
        }
        if (p.mode > TINYGLTF_MODE_TRIANGLE_FAN)
            fail(where, "primitive mode " + std::to_string(p.mode) + " does not exist");
        const auto pos = p.attributes.find("POSITION");
        if (pos == p.attributes.end()) fail(where, "has no POSITION");
        MeshPart part;
        TriangleMesh& m = part.mesh;
        m.positions = floats(pos->second, 3, where + " POSITION");
        const std::size_t nv = m.positions.size() / 3;
        if (const auto it = p.attributes.find("NORMAL"); it != p.attributes.end()) {
            m.normals = floats(it->second, 3, where + " NORMAL");
            if (m.normals.size() != m.positions.size())
                fail(where, "NORMAL count differs from POSITION");
        }
        // The uv sets the material's textures read (TEXCOORD_0 without textures).
        part.material = p.material >= 0 ? material(p.material) : -1;
        const FileMaterial* fm =
            part.material >= 0 ? &out_.materials[std::size_t(part.material)] : nullptr;
        uv_set(p, fm ? std::max(fm->tex_coord, 0) : 0, fm && fm->tex_coord >= 0, nv, m.uvs, where);
        if (fm && fm->tex_coord2 >= 0) uv_set(p, fm->tex_coord2, true, nv, m.uvs2, where);
        if (const auto it = p.attributes.find("COLOR_0"); it != p.attributes.end())
            vertex_colors(it->second, nv, part, where);
        if (p.indices >= 0) {
            m.indices = indices(p.indices, where + " indices");
        } else {
            for (uint32_t i = 0; i < nv; ++i) m.indices.push_back(i);
        }
        m.indices = gltf_triangle_list(std::move(m.indices), p.mode < 0 ? 4 : p.mode);
        if (m.indices.size() % 3 != 0) fail(where, "index count is not a multiple of 3");
        for (uint32_t i : m.indices)
            if (i >= nv)
                fail(where, "index " + std::to_string(i) + " outside its " + std::to_string(nv) +
                                " vertices");
        // Degenerate triangles are skipped and counted, as for OBJ.
        std::vector<uint32_t> kept;
        for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
            Vec3 a = m.vertex(m.indices[t]), b = m.vertex(m.indices[t + 1]),
                 c = m.vertex(m.indices[t + 2]);
            if (length_squared(cross(b - a, c - a)) == 0.f) {
                ++out_.degenerate_skipped;
                continue;
            }
            kept.insert(kept.end(), &m.indices[t], &m.indices[t] + 3);
        }
        if (kept.empty()) return;
        m.indices = std::move(kept);
        part.has_normals = !m.normals.empty();
        placed_triangles_ += m.indices.size() / 3;
        if (placed_triangles_ > kMaxPlacedTriangles)
            fail(where, "the scene places more than " + std::to_string(kMaxPlacedTriangles) +
                            " triangles (meshes repeated by the node graph count each time)");
        m.transform(xf);
        out_.parts.push_back(std::move(part));
    }

    // TEXCOORD_<set> of primitive p into `uvs` (v flipped: glTF's runs down the image, foton's
    // textures take v = 0 at the bottom); a set that textures read but the primitive lacks is
    // noted.
    void uv_set(const tinygltf::Primitive& p, int set, bool read, std::size_t nv,
                std::vector<float>& uvs, const std::string& where) {
        const std::string name = "TEXCOORD_" + std::to_string(set);
        const auto it = p.attributes.find(name);
        if (it == p.attributes.end()) {
            if (read)
                note(where + ": its material's textures read " + name +
                     ", which it lacks (read at pbrt's default parametrisation)");
            return;
        }
        uvs = floats(it->second, 2, where + " " + name);
        if (uvs.size() != 2 * nv) fail(where, name + " count differs from POSITION");
        for (std::size_t i = 1; i < uvs.size(); i += 2) uvs[i] = 1.f - uvs[i];
    }

    // COLOR_0 (RGB or RGBA; floats or normalised integers) into the mesh, and the material
    // told to multiply its base colour by it. Its alpha is not read.
    void vertex_colors(int a, std::size_t nv, MeshPart& part, const std::string& where) {
        const int n =
            std::size_t(a) < g_.accessors.size() && a >= 0
                ? tinygltf::GetNumComponentsInType(uint32_t(g_.accessors[std::size_t(a)].type))
                : 3;
        if (n != 3 && n != 4) fail(where, "COLOR_0 must be VEC3 or VEC4");
        const std::vector<float> c = floats(a, n, where + " COLOR_0");
        if (c.size() != std::size_t(n) * nv) fail(where, "COLOR_0 count differs from POSITION");
        bool alpha = false;
        part.mesh.colors.reserve(3 * nv);
        for (std::size_t i = 0; i < nv; ++i) {
            const float* q = &c[std::size_t(n) * i];
            if (!(q[0] >= 0.f && q[1] >= 0.f && q[2] >= 0.f))
                fail(where, "COLOR_0 holds a negative colour");
            part.mesh.colors.insert(part.mesh.colors.end(), q, q + 3);
            alpha = alpha || (n == 4 && q[3] < 1.f);
        }
        if (part.material < 0) {
            // glTF's default material (white, metallic 1, roughness 1) tinted by the colours.
            FileMaterial f;
            f.name = "gltf default material";
            f.diffuse = RGB{1.f};
            f.metallic = 1.f;
            f.dielectric_specular = true;
            f.emission_given = true;
            f.vertex_colors = true;
            part.material = int(out_.materials.size());
            out_.materials.push_back(f);
        } else {
            out_.materials[std::size_t(part.material)].vertex_colors = true;
        }
        if (alpha) note(where + ": COLOR_0's alpha ignored (its colour is read)");
    }

    // The FileMaterial of glTF material i (made once).
    int material(int i) {
        if (std::size_t(i) >= g_.materials.size())
            fail("material " + std::to_string(i), "does not exist");
        if (const auto it = materials_.find(i); it != materials_.end()) return it->second;
        const tinygltf::Material& gm = g_.materials[std::size_t(i)];
        const std::string where = "material " + std::to_string(i) + " '" + gm.name + "'";
        FileMaterial f;
        f.name = gm.name.empty() ? "gltf material " + std::to_string(i) : gm.name;
        const auto& pbr = gm.pbrMetallicRoughness;
        // A texture reference (TextureInfo or NormalTextureInfo): its image into `map`, its
        // KHR_texture_transform into `uv`, its uv set the material's (gltf_use_tex_coord).
        auto texture = [&](const auto& info, const char* name, bool linear, std::string& map,
                           UvMap& uv) {
            if (info.index < 0) return;
            map = image(info.index, where, linear);
            try {
                int set = info.texCoord;
                uv = gltf_uv_map(info.extensions, set);
                uv.set = gltf_use_tex_coord(f, set, name, out_.notes, path_ + ": " + where);
            } catch (const std::invalid_argument& e) {
                fail(where, e.what());
            }
        };
        if (pbr.baseColorFactor.size() >= 3)
            f.diffuse = RGB{float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]),
                            float(pbr.baseColorFactor[2])};
        if (!(f.diffuse.r >= 0.f && f.diffuse.g >= 0.f && f.diffuse.b >= 0.f) ||
            f.diffuse.max_component() > 1.f)
            fail(where, "baseColorFactor must be in [0, 1]");
        f.metallic = float(pbr.metallicFactor);
        f.roughness = float(pbr.roughnessFactor);
        if (!(f.metallic >= 0.f && f.metallic <= 1.f && f.roughness >= 0.f && f.roughness <= 1.f))
            fail(where, "metallicFactor and roughnessFactor must be in [0, 1]");
        texture(pbr.baseColorTexture, "baseColorTexture", false, f.diffuse_map, f.diffuse_uv);
        f.dielectric_specular = true;
        texture(pbr.metallicRoughnessTexture, "metallicRoughnessTexture", true,
                f.metallic_roughness_map, f.metallic_roughness_uv);
        if (gm.emissiveFactor.size() == 3) {
            f.emission = RGB{float(gm.emissiveFactor[0]), float(gm.emissiveFactor[1]),
                             float(gm.emissiveFactor[2])};
            if (const auto it = gm.extensions.find("KHR_materials_emissive_strength");
                it != gm.extensions.end() && it->second.Has("emissiveStrength"))
                f.emission *= float(it->second.Get("emissiveStrength").GetNumberAsDouble());
            if (!(f.emission.r >= 0.f && f.emission.g >= 0.f && f.emission.b >= 0.f) ||
                !std::isfinite(f.emission.max_component()))
                fail(where, "emission must be finite and not negative");
        }
        auto ignored = [&](bool present, const char* what) {
            if (present) note(where + ": " + what + " ignored");
        };
        // Tangents from the uv (the file's TANGENT attribute is not read).
        texture(gm.normalTexture, "normalTexture", true, f.normal_map, f.normal_uv);
        f.normal_scale = float(gm.normalTexture.scale);
        if (!std::isfinite(f.normal_scale)) fail(where, "normalTexture scale must be finite");
        // Ambient occlusion baked for rasterisers: light transport computes its own.
        ignored(gm.occlusionTexture.index >= 0, "occlusionTexture (transport computes occlusion)");
        f.emission_given = true;  // glTF's emissiveFactor defaults to black
        texture(gm.emissiveTexture, "emissiveTexture", false, f.emission_map, f.emission_uv);
        try {
            gltf_alpha_mode(gm, f);
            gltf_material_extensions(gm, f, out_.notes, path_ + ": " + where);
        } catch (const std::invalid_argument& e) {
            fail(where, e.what());
        }
        if (f.clearcoat_texture >= 0) f.clearcoat_map = image(f.clearcoat_texture, where, true);
        if (f.transmission_texture >= 0)
            f.transmission_map = image(f.transmission_texture, where, true);
        if (f.specular_texture >= 0) f.specular_map = image(f.specular_texture, where, true);
        if (f.clearcoat_roughness_texture >= 0)
            f.clearcoat_roughness_map = image(f.clearcoat_roughness_texture, where, true);
        const int index = int(out_.materials.size());
        out_.materials.push_back(f);
        return materials_[i] = index;
    }

    // The key of texture t's image in MeshFile::embedded_images, decoded once.
    std::string image(int t, const std::string& where, bool linear = false) {
        if (t < 0 || std::size_t(t) >= g_.textures.size())
            fail(where, "texture " + std::to_string(t) + " does not exist");
        const int src = g_.textures[std::size_t(t)].source;
        if (src < 0 || std::size_t(src) >= g_.images.size())
            fail(where, "texture " + std::to_string(t) + " has no image");
        // The texture's sampler: its wrap modes are the image's (one decoded per mode pair).
        TextureWrap wrap_s = TextureWrap::Repeat, wrap_t = TextureWrap::Repeat;
        if (const int smp = g_.textures[std::size_t(t)].sampler; smp >= 0) {
            if (std::size_t(smp) >= g_.samplers.size())
                fail(where, "texture " + std::to_string(t) + " names sampler " +
                                std::to_string(smp) + ", which does not exist");
            const tinygltf::Sampler& s = g_.samplers[std::size_t(smp)];
            try {
                wrap_s = gltf_wrap(s.wrapS);
                wrap_t = gltf_wrap(s.wrapT);
            } catch (const std::invalid_argument& e) {
                fail(where + ", sampler " + std::to_string(smp), e.what());
            }
            if (s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST)
                note(where + ", sampler " + std::to_string(smp) +
                     ": magFilter NEAREST read as LINEAR (bilinear)");
        }
        std::string key = path_ + "#image" + std::to_string(src) + (linear ? "#linear" : "");
        if (wrap_s != TextureWrap::Repeat || wrap_t != TextureWrap::Repeat)
            key += "#wrap" + std::to_string(int(wrap_s)) + std::to_string(int(wrap_t));
        if (out_.embedded_images.count(key)) return key;
        const tinygltf::Image& im = g_.images[std::size_t(src)];
        if (im.image.empty() && !im.uri.empty() && im.uri.rfind("data:", 0) != 0)
            fail(where + ", image " + std::to_string(src),
                 gltf_unread_image_reason(load_warnings_, im.uri));
        try {
            TextureImage& decoded = out_.embedded_images[key] =
                gltf_decode_image(im, im.uri.empty() ? key : im.uri, linear);
            decoded.wrap_s = wrap_s;
            decoded.wrap_t = wrap_t;
        } catch (const std::invalid_argument& e) {
            fail(where + ", image " + std::to_string(src), e.what());
        }
        return key;
    }

    void node(int i, const Affine& parent, int depth) {
        if (i < 0 || std::size_t(i) >= g_.nodes.size())
            fail("node " + std::to_string(i), "does not exist");
        if (depth > 64) fail("node " + std::to_string(i), "nodes nest deeper than 64 (a cycle?)");
        // A node listed as a child twice is placed twice, and so is everything below it: 24
        // such nodes in 900 bytes would ask for 2^24 copies.
        if (++visits_ > kMaxNodePlacements)
            fail("node " + std::to_string(i),
                 "the node graph places more than " + std::to_string(kMaxNodePlacements) +
                     " nodes (children listed more than once multiply)");
        const tinygltf::Node& n = g_.nodes[std::size_t(i)];
        const Affine xf = parent * gltf_node_transform(n);
        if (n.mesh >= 0) {
            if (std::size_t(n.mesh) >= g_.meshes.size())
                fail("node " + std::to_string(i),
                     "mesh " + std::to_string(n.mesh) + " does not exist");
            const tinygltf::Mesh& mesh = g_.meshes[std::size_t(n.mesh)];
            for (std::size_t k = 0; k < mesh.primitives.size(); ++k)
                primitive(mesh.primitives[k], xf,
                          "mesh " + std::to_string(n.mesh) + " primitive " + std::to_string(k));
        }
        try {
            gltf_node_extras(g_, n, xf, out_, path_ + ": node " + std::to_string(i));
        } catch (const std::invalid_argument& e) {
            fail("node " + std::to_string(i), e.what());
        }
        for (int c : n.children) node(c, xf, depth + 1);
    }

    MeshFile run() {
        // A file that cannot be read without an extension says so; one foton does not read
        // (mesh compression, other texture formats, ...) is an error, as the spec asks.
        for (const std::string& ext : g_.extensionsRequired)
            if (!gltf_extension_read(ext))
                fail("extensionsRequired", "the file requires " + ext +
                                               ", which foton does not read (it reads " +
                                               gltf_extensions_read() + ")");
        if (g_.scenes.empty()) {
            // No scene: every root node (one that is nobody's child).
            std::vector<bool> child(g_.nodes.size(), false);
            for (const tinygltf::Node& n : g_.nodes)
                for (int c : n.children)
                    if (c >= 0 && std::size_t(c) < child.size()) child[std::size_t(c)] = true;
            for (std::size_t i = 0; i < g_.nodes.size(); ++i)
                if (!child[i]) node(int(i), Affine{}, 0);
        } else {
            const int s = g_.defaultScene >= 0 ? g_.defaultScene : 0;
            if (std::size_t(s) >= g_.scenes.size())
                fail("scene", "the default scene does not exist");
            for (int n : g_.scenes[std::size_t(s)].nodes) node(n, Affine{}, 0);
        }
        if (!g_.animations.empty()) note("animations ignored (the rest pose is rendered)");
        if (!g_.skins.empty()) note("skins ignored (the rest pose is rendered)");
        if (out_.parts.empty()) throw InputError(path_, 0, "no triangles in the glTF file");
        return std::move(out_);
    }

  private:
    static constexpr uint64_t kMaxNodePlacements = uint64_t(1) << 18;
    static constexpr uint64_t kMaxPlacedTriangles = uint64_t(1) << 26;
    const tinygltf::Model& g_;
    std::string path_;
    std::string load_warnings_;
    GltfAccessors accessors_;
    MeshFile out_;
    std::map<int, int> materials_;
    uint64_t visits_ = 0, placed_triangles_ = 0;
};

}  // namespace

MeshFile parse_gltf(const std::string& bytes, const std::string& name, const std::string& base_dir,
                    bool binary) {
    // The parser recurses per level of nesting: a deep file would overflow the stack.
    const std::string_view json = binary ? glb_json_chunk(bytes) : std::string_view(bytes);
    if (json_nesting_depth(json) > kMaxGltfJsonDepth)
        throw InputError(name, 0,
                         "malformed glTF: JSON nested deeper than " +
                             std::to_string(kMaxGltfJsonDepth) + " levels");
    tinygltf::TinyGLTF loader;
    GltfFileRoot root{base_dir};
    guard_gltf_loader(loader, root);
    tinygltf::Model model;
    std::string err, warn;
    const bool ok =
        binary ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                             reinterpret_cast<const unsigned char*>(bytes.data()),
                                             unsigned(bytes.size()), base_dir)
               : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(),
                                            unsigned(bytes.size()), base_dir);
    if (!ok) {
        while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
        throw InputError(name, 0,
                         "malformed glTF: " + (err.empty() ? std::string("unreadable") : err));
    }
    GltfReader reader(model, name, warn);
    MeshFile out = reader.run();
    if (!warn.empty()) out.notes.push_back(name + ": " + warn);
    return out;
}

MeshFile load_gltf(const std::string& path) {
    const std::string ext = lower_extension(path);
    const std::string dir = std::filesystem::path(path).parent_path().string();
    return parse_gltf(read_input_file(path, kMaxMeshFileBytes, "mesh file"), path,
                      dir.empty() ? "." : dir, ext == ".glb");
}

}  // namespace foton
