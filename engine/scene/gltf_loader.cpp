// glTF 2.0 through tinygltf (Debian's libtinygltf-dev): the JSON and its buffers and images
// are parsed by the library; every index, offset and stride it hands over is checked here
// before use, so a malformed file is an InputError, never a read out of bounds.
#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>

#include "engine/core/error.h"
#include "engine/core/input_file.h"
#include "gltf_inputs.h"
#include "gltf_scene_parts.h"
#include "mesh_file.h"

namespace foton {

namespace {

class GltfReader {
  public:
    // `load_warnings`: tinygltf's, which say why an external image could not be read.
    GltfReader(const tinygltf::Model& model, std::string path, std::string load_warnings)
        : g_(model), path_(std::move(path)), load_warnings_(std::move(load_warnings)) {}

    [[noreturn]] void fail(const std::string& where, const std::string& what) const {
        throw InputError(path_, 0, where + ": " + what);
    }
    void note(const std::string& what) { out_.notes.push_back(path_ + ": " + what); }

    // The elements of accessor `a` as floats (normalized integers mapped to [0, 1]), `n`
    // components each, or indices when `as_index`.
    std::vector<float> floats(int a, int n, const std::string& where) const {
        std::vector<float> out;
        read(a, n, where, false, [&](double v) { out.push_back(float(v)); });
        return out;
    }
    std::vector<uint32_t> indices(int a, const std::string& where) const {
        std::vector<uint32_t> out;
        read(a, 1, where, true, [&](double v) { out.push_back(uint32_t(v)); });
        return out;
    }

    void read(int a, int n, const std::string& where, bool as_index,
              const std::function<void(double)>& put) const {
        if (a < 0 || std::size_t(a) >= g_.accessors.size())
            fail(where, "accessor " + std::to_string(a) + " does not exist");
        const tinygltf::Accessor& acc = g_.accessors[std::size_t(a)];
        const std::string at = where + ", accessor " + std::to_string(a);
        if (acc.sparse.isSparse) fail(at, "sparse accessors are not supported");
        if (tinygltf::GetNumComponentsInType(uint32_t(acc.type)) != n)
            fail(at, "has " + std::to_string(tinygltf::GetNumComponentsInType(uint32_t(acc.type))) +
                         " components, expected " + std::to_string(n));
        const int ct = acc.componentType;
        const bool ok_type =
            as_index ? (ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                        ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
                        ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
                     : (ct == TINYGLTF_COMPONENT_TYPE_FLOAT ||
                        (acc.normalized && (ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                            ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT)));
        if (!ok_type) fail(at, "component type " + std::to_string(ct) + " is not allowed here");
        if (acc.bufferView < 0 || std::size_t(acc.bufferView) >= g_.bufferViews.size())
            fail(at, "has no valid bufferView");
        const tinygltf::BufferView& view = g_.bufferViews[std::size_t(acc.bufferView)];
        if (view.buffer < 0 || std::size_t(view.buffer) >= g_.buffers.size())
            fail(at, "its bufferView names no valid buffer");
        const std::vector<unsigned char>& data = g_.buffers[std::size_t(view.buffer)].data;
        const int stride = acc.ByteStride(view);
        const int size = tinygltf::GetComponentSizeInBytes(uint32_t(ct));
        if (stride <= 0 || size <= 0) fail(at, "invalid byte stride");
        // Every element must lie inside the view, and the view inside the buffer.
        if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
            fail(at, "its bufferView lies outside the buffer");
        if (acc.count > 0) {
            const uint64_t last = uint64_t(acc.byteOffset) +
                                  uint64_t(acc.count - 1) * uint64_t(stride) +
                                  uint64_t(size) * uint64_t(n);
            if (last > view.byteLength) fail(at, "reads beyond its bufferView");
        }
        const unsigned char* base = data.data() + view.byteOffset + acc.byteOffset;
        for (std::size_t i = 0; i < acc.count; ++i) {
            const unsigned char* e = base + i * std::size_t(stride);
            for (int k = 0; k < n; ++k) {
                const unsigned char* c = e + std::size_t(k * size);
                double v;
                if (ct == TINYGLTF_COMPONENT_TYPE_FLOAT) {
                    float f;
                    std::memcpy(&f, c, 4);
                    if (!std::isfinite(f)) fail(at, "holds NaN or infinite values");
                    v = f;
                } else if (ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
                    v = as_index ? double(*c) : double(*c) / 255.0;
                } else if (ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
                    uint16_t s;
                    std::memcpy(&s, c, 2);
                    v = as_index ? double(s) : double(s) / 65535.0;
                } else {
                    uint32_t u;
                    std::memcpy(&u, c, 4);
                    v = double(u);
                }
                put(v);
            }
        }
    }

    static Affine node_transform(const tinygltf::Node& n) {
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
        const double R[3][3] = {
            {1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
            {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
            {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) xf.m[r][c] = float(R[r][c] * s[c]);
            xf.m[r][3] = float(t[r]);
        }
        return xf;
    }

    void primitive(const tinygltf::Primitive& p, const Affine& xf, const std::string& where) {
        if (p.mode != TINYGLTF_MODE_TRIANGLES && p.mode != -1) {
            note(where + ": primitive mode " + std::to_string(p.mode) +
                 " left out (triangles only)");
            return;
        }
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
        // The uv set the material's textures read (TEXCOORD_0 without textures).
        part.material = p.material >= 0 ? material(p.material) : -1;
        const int set = part.material >= 0
                            ? std::max(out_.materials[std::size_t(part.material)].tex_coord, 0)
                            : 0;
        const std::string uv_name = "TEXCOORD_" + std::to_string(set);
        if (const auto it = p.attributes.find(uv_name); it != p.attributes.end()) {
            m.uvs = floats(it->second, 2, where + " " + uv_name);
            if (m.uvs.size() != 2 * nv) fail(where, uv_name + " count differs from POSITION");
            // glTF's v runs down the image; foton's textures take v = 0 at the bottom.
            for (std::size_t i = 1; i < m.uvs.size(); i += 2) m.uvs[i] = 1.f - m.uvs[i];
        } else if (part.material >= 0 &&
                   out_.materials[std::size_t(part.material)].tex_coord >= 0) {
            note(where + ": its material's textures read " + uv_name +
                 ", which it lacks (read at pbrt's default parametrisation)");
        }
        if (p.indices >= 0) {
            m.indices = indices(p.indices, where + " indices");
        } else {
            for (uint32_t i = 0; i < nv; ++i) m.indices.push_back(i);
        }
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
                gltf_use_tex_coord(f, set, name, out_.notes, path_ + ": " + where);
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
        if (gm.normalTexture.index >= 0 && gm.normalTexture.scale != 1.0)
            note(where + ": normalTexture scale " + std::to_string(gm.normalTexture.scale) +
                 " ignored (read as 1)");
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
        const std::string key = path_ + "#image" + std::to_string(src) + (linear ? "#linear" : "");
        if (out_.embedded_images.count(key)) return key;
        const tinygltf::Image& im = g_.images[std::size_t(src)];
        if (im.image.empty() && !im.uri.empty() && im.uri.rfind("data:", 0) != 0)
            fail(where + ", image " + std::to_string(src),
                 gltf_unread_image_reason(load_warnings_, im.uri));
        try {
            out_.embedded_images[key] =
                gltf_decode_image(im, im.uri.empty() ? key : im.uri, linear);
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
        const Affine xf = parent * node_transform(n);
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
