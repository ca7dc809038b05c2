#include "mesh_file.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "engine/core/error.h"
#include "engine/core/input_file.h"
#include "metals.h"
#include "obj_loader.h"
#include "ply_reader.h"
#include "scene.h"

namespace foton {

namespace {

// An OBJ file: its mtllib files read, and its triangles split by material into parts.
MeshFile load_obj_file(const std::string& path) {
    ObjLoadResult r = load_obj(path);
    MeshFile out;
    out.degenerate_skipped = r.degenerate_skipped;
    const std::string dir = std::filesystem::path(path).parent_path().string();
    std::map<std::string, FileMaterial> library;
    for (const ObjLoadResult::Library& lib : r.libraries) {
        const std::string lib_path = (std::filesystem::path(dir) / lib.file).string();
        const std::string problem = input_file_problem(lib_path, kMaxMeshFileBytes);
        if (!problem.empty())
            throw InputError(path, lib.line,
                             "mtllib '" + lib.file +
                                 "': " + (problem == "not found" ? "file not found" : problem) +
                                 " (looked for " + lib_path + ")");
        std::map<std::string, FileMaterial> m =
            parse_mtl(read_input_file(lib_path, kMaxMeshFileBytes, "material file"), lib_path,
                      std::filesystem::path(lib_path).parent_path().string(), out.notes);
        library.merge(m);  // the first library to define a name wins
    }
    std::vector<int> index(r.material_names.size(), -1);
    for (std::size_t i = 0; i < r.material_names.size(); ++i) {
        const auto it = library.find(r.material_names[i]);
        if (it == library.end()) {
            if (r.libraries.empty())
                out.notes.push_back(path + ":" + std::to_string(r.material_lines[i]) +
                                    ": usemtl '" + r.material_names[i] +
                                    "' without any mtllib: the object's material is used");
            else
                throw InputError(
                    path, r.material_lines[i],
                    "usemtl '" + r.material_names[i] + "': no such material in the mtllib files");
            continue;
        }
        index[i] = int(out.materials.size());
        out.materials.push_back(it->second);
    }
    // One part per material in order of first use; triangles keep their order within it.
    const TriangleMesh& m = r.mesh;
    std::map<int, std::size_t> part_of;
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        const int32_t name = r.triangle_material[t];
        const int mat = name < 0 ? -1 : index[std::size_t(name)];
        auto [it, inserted] = part_of.try_emplace(mat, out.parts.size());
        if (inserted) {
            MeshPart part;
            part.material = mat;
            part.has_normals = !m.normals.empty();
            part.mesh.name = m.name;
            out.parts.push_back(std::move(part));
        }
        out.parts[it->second].mesh.indices.insert(out.parts[it->second].mesh.indices.end(),
                                                  &m.indices[3 * t], &m.indices[3 * t] + 3);
    }
    // Each part keeps the vertices it uses (all of them when there is only one part).
    for (MeshPart& part : out.parts) {
        if (out.parts.size() == 1) {
            std::vector<uint32_t> idx = std::move(part.mesh.indices);
            part.mesh = r.mesh;
            part.mesh.indices = std::move(idx);
            continue;
        }
        std::vector<uint32_t> remap(m.num_vertices(), UINT32_MAX);
        TriangleMesh& pm = part.mesh;
        for (uint32_t& v : pm.indices) {
            if (remap[v] == UINT32_MAX) {
                remap[v] = uint32_t(pm.positions.size() / 3);
                pm.positions.insert(pm.positions.end(), &m.positions[3 * v],
                                    &m.positions[3 * v] + 3);
                if (!m.normals.empty())
                    pm.normals.insert(pm.normals.end(), &m.normals[3 * v], &m.normals[3 * v] + 3);
                if (!m.uvs.empty()) pm.uvs.insert(pm.uvs.end(), &m.uvs[2 * v], &m.uvs[2 * v] + 2);
            }
            v = remap[v];
        }
    }
    for (MeshPart& part : out.parts) part.has_normals = r.has_normals || !part.mesh.normals.empty();
    return out;
}

}  // namespace

MeshFile load_mesh_file(const std::string& path) {
    const std::string ext = lower_extension(path);
    if (ext == ".obj") return load_obj_file(path);
    if (ext == ".gltf" || ext == ".glb") return load_gltf(path);
    if (ext == ".ply") {
        MeshFile out;
        MeshPart part;
        part.mesh = load_ply(path);
        part.has_normals = !part.mesh.normals.empty();
        out.parts.push_back(std::move(part));
        return out;
    }
    throw InputError(path, 0, "unknown mesh format '" + ext + "' (.obj, .ply, .gltf, .glb)");
}

namespace {

// A material's image (a file, or one the glTF file embeds) in Scene::texture_images, decoded
// once per name and encoding (a normal map is read linearly, a colour map as sRGB).
uint32_t file_image(Scene& scene, const MeshFile& file, std::map<std::string, uint32_t>& images,
                    const std::string& name, bool linear) {
    const std::string key = linear ? name + "#linear" : name;
    if (const auto it = images.find(key); it != images.end()) return it->second;
    const auto emb = file.embedded_images.find(name);
    scene.texture_images.push_back(
        emb != file.embedded_images.end() ? emb->second : load_texture_image(name, linear));
    return images[key] = uint32_t(scene.texture_images.size() - 1);
}

// An image texture of the material (its image decoded once through file_image) read through
// `uv` and scaled by `scale`, added to Scene::textures; returns its index.
int32_t image_texture(Scene& scene, const MeshFile& file, std::map<std::string, uint32_t>& images,
                      const std::string& name, bool linear, const UvMap& uv,
                      const RGB& scale = RGB{1.f}) {
    Texture tx;
    tx.kind = TextureKind::Image;
    tx.image = file_image(scene, file, images, name, linear);
    tx.uv = uv;
    tx.scale = scale;
    scene.textures.push_back(tx);
    return int32_t(scene.textures.size() - 1);
}

// A parameter of one of the material's lobes set per hit from a texture
// (Material::float_params).
void add_textured_param(Material& m, const Material::FloatParam& p) {
    if (!m.add_float_param(p))
        throw InputError(m.name, 0, "too many textured parameters in one material");
}
// The same for the lobe added last, from `texture` when there is one (>= 0).
void last_lobe_param(Material& m, int32_t texture, LobeParam target, uint8_t channel,
                     Material::Remap remap = Material::Remap::None, float k = 1.f) {
    if (texture >= 0)
        add_textured_param(m, {texture, uint8_t(m.bsdf.size() - 1), target, remap, channel, k});
}

// glTF's clear coat (KHR_materials_clearcoat): the specification mixes the material with the
// coat's specular reflection by clearcoat times the coat's Fresnel term, F of index 1.5. As the
// dielectric reflection over the diffuse base above, the base keeps what the coat lets through
// at normal incidence (1 - clearcoat F0, F0 = 0.04) and the coat is a GGX lobe of that Fresnel
// weighted by clearcoat (a textured metallic weight multiplies the base's lobes as well). Its
// textures set both per hit: clearcoat c = factor x red, alpha = (factor x green)^2.
void add_clearcoat(Scene& scene, const FileMaterial& f, const MeshFile& file,
                   std::map<std::string, uint32_t>& images, Material& m) {
    const float c = std::clamp(f.clearcoat, 0.f, 1.f);
    Fresnel coat;
    coat.kind = FresnelKind::Dielectric;
    coat.ior = 1.5f;
    const int base_lobes = m.bsdf.size();
    int32_t tex = -1;
    if (!f.clearcoat_map.empty()) {
        // 1 - 0.04 v on every lobe below, v on the coat, v = c x red.
        tex = image_texture(scene, file, images, f.clearcoat_map, true, f.clearcoat_uv, RGB{c});
        for (int i = 0; i < base_lobes; ++i)
            add_textured_param(
                m, {tex, uint8_t(i), LobeParam::WeightComplement, Material::Remap::None, 1, 0.04f});
    } else {
        m.bsdf.scale(1.f - c * 0.04f);
        m.base_color *= 1.f - c * 0.04f;
    }
    const RGB weight{f.clearcoat_map.empty() ? c : 1.f};
    const float alpha = std::min(f.clearcoat_roughness * f.clearcoat_roughness, 2.f);
    if (alpha < 0.002f && f.clearcoat_roughness_map.empty()) {
        m.bsdf.add(Lobe::mirror(weight, coat));
    } else {
        const float a = std::max(alpha, 1e-3f);
        m.bsdf.add(Lobe::microfacet(weight, MicrofacetDistribution::trowbridge_reitz(a, a), coat));
    }
    // The coat's own parameters, on the lobe just added.
    last_lobe_param(m, tex, LobeParam::Weight, 1);
    if (!f.clearcoat_roughness_map.empty())
        last_lobe_param(
            m,
            image_texture(scene, file, images, f.clearcoat_roughness_map, true,
                          f.clearcoat_roughness_uv, RGB{1.f, f.clearcoat_roughness, 1.f}),
            LobeParam::Alpha, 2, Material::Remap::Square);
}

// What an MTL map_Bump image holds: grey texels (channels within 2/255) are heights; texels
// around (0.5, 0.5, 1) on average, blue above red and green, are a tangent-space normal map
// (what Blender and others export under map_Bump); anything else is neither.
enum class BumpImage { Height, Normal, Neither };
BumpImage classify_bump_image(const TextureImage& img) {
    double r = 0.0, g = 0.0, b = 0.0;
    float spread = 0.f;
    for (const RGB& t : img.texels) {
        r += t.r;
        g += t.g;
        b += t.b;
        spread = std::max({spread, std::fabs(t.r - t.g), std::fabs(t.g - t.b)});
    }
    if (spread <= 2.f / 255.f + 1e-6f) return BumpImage::Height;
    const double n = double(std::max<std::size_t>(img.texels.size(), 1));
    r /= n;
    g /= n;
    b /= n;
    if (std::fabs(r - 0.5) < 0.2 && std::fabs(g - 0.5) < 0.2 && b > 0.7 && b > r && b > g)
        return BumpImage::Normal;
    return BumpImage::Neither;
}

// MTL's map_Bump: a height map bumps the shading normal (heights in scene units: the grey
// value times -bm, the OBJ specification's multiplier); a normal map turns it, unless the
// material has its own `norm` (which then wins).
void add_bump_map(Scene& scene, const FileMaterial& f, const MeshFile& file,
                  std::map<std::string, uint32_t>& images, Material& m) {
    const uint32_t im = file_image(scene, file, images, f.bump_map, true);
    switch (classify_bump_image(scene.texture_images[im])) {
        case BumpImage::Height:
            m.bump = image_texture(scene, file, images, f.bump_map, true, f.normal_uv,
                                   RGB{f.bump_multiplier});
            return;
        case BumpImage::Normal:
            if (f.normal_map.empty())
                m.normal_map = image_texture(scene, file, images, f.bump_map, true, f.normal_uv);
            return;
        case BumpImage::Neither:
            throw InputError(f.bump_map, 0,
                             "material '" + f.name +
                                 "': its map_Bump image is neither a height map (grey) nor a "
                                 "tangent-space normal map (bluish, about (0.5, 0.5, 1))");
    }
}

// The lobes of a file's non-glass material: a Lambert of the diffuse colour, MTL's Phong
// highlight or mirror, glTF's metal (a conductor of the base colour's reflectance, GGX of alpha
// = roughness^2), its dielectric reflection and its transmission. With glTF's
// metallic-roughness texture the metal and dielectric parts are weighted and roughened per hit
// (Material::float_params): lobes at full weight, then v or 1 - v of the texture's metallic.
void add_surface_lobes(Scene& scene, const FileMaterial& f, const MeshFile& file,
                       std::map<std::string, uint32_t>& images, Material& m) {
    int32_t mr = -1;
    if (!f.metallic_roughness_map.empty()) {
        // glTF: the factors times the channels.
        mr = image_texture(scene, file, images, f.metallic_roughness_map, true,
                           f.metallic_roughness_uv, RGB{1.f, f.roughness, f.metallic});
    }
    auto param = [&](LobeParam target, uint8_t channel, Material::Remap remap) {
        last_lobe_param(m, mr, target, channel, remap);
    };
    auto alpha_param = [&] { param(LobeParam::Alpha, 2, Material::Remap::Square); };
    // glTF's transmission texture: its red times the factor is the transmitting share per
    // hit, so the lobes are made at full share and weighted v (transmission) or 1 - v.
    int32_t tr = -1;
    if (!f.transmission_map.empty())
        tr = image_texture(scene, file, images, f.transmission_map, true, f.transmission_uv,
                           RGB{std::clamp(f.transmission, 0.f, 1.f)});
    auto trans_param = [&](LobeParam target) { last_lobe_param(m, tr, target, 1); };
    // Per hit with a texture, else the factor now.
    const float metal = mr >= 0 ? 1.f : std::clamp(f.metallic, 0.f, 1.f);
    const float dielectric = mr >= 0 ? 1.f : 1.f - metal;
    const float alpha = std::min(f.roughness * f.roughness, 2.f);
    const bool smooth = mr < 0 && alpha < 0.002f;
    const auto ggx =
        MicrofacetDistribution::trowbridge_reitz(std::max(alpha, 1e-3f), std::max(alpha, 1e-3f));
    // glTF's transmission replaces that much of the dielectric base's diffuse part; its
    // reflection takes the rest's Fresnel share.
    const float trans = tr >= 0 ? 0.f : std::clamp(f.transmission, 0.f, 1.f);
    Fresnel glass;
    glass.kind = FresnelKind::Dielectric;
    glass.ior = f.ior;
    const float f0_ior = (f.ior - 1.f) * (f.ior - 1.f) / ((f.ior + 1.f) * (f.ior + 1.f));
    const RGB t = f.dielectric_tint;
    const RGB f0_tinted{std::min(t.r * f0_ior, 1.f), std::min(t.g * f0_ior, 1.f),
                        std::min(t.b * f0_ior, 1.f)};
    const bool tinted = t.r != 1.f || t.g != 1.f || t.b != 1.f;
    if (tinted) glass = Fresnel::schlick(f0_tinted);
    // The diffuse base keeps what the reflection leaves at normal incidence. glTF's
    // specularTexture sets the reflection's strength v per hit: the reflection made at full
    // strength and weighted v, the base 1 - v F0.
    int32_t spec = -1;
    if (!f.specular_map.empty() && f.dielectric_specular)
        spec = image_texture(scene, file, images, f.specular_map, true, f.specular_uv,
                             RGB{f.dielectric_weight});
    auto spec_param = [&](LobeParam target, float k) {
        last_lobe_param(m, spec, target, 4, Material::Remap::None, k);
    };
    const float strength = spec >= 0 ? 0.f : f.dielectric_weight;
    const float f0 = strength * f0_tinted.max_component();
    // Diffuse and highlight (or mirror) share what arrives: scaled so they sum to at most 1.
    RGB kd = f.diffuse * (dielectric * (1.f - trans) * (f.dielectric_specular ? 1.f - f0 : 1.f));
    RGB ks = f.specular;
    const float total = (kd + ks).max_component();
    if (total > 1.f) {
        kd *= 1.f / total;
        ks *= 1.f / total;
    }
    m.base_color = kd;
    m.bsdf.add(Lobe::lambert(kd));
    param(LobeParam::WeightComplement, 3, Material::Remap::None);
    trans_param(LobeParam::WeightComplement);
    spec_param(LobeParam::WeightComplement, f0_tinted.max_component());
    if (!f.diffuse_map.empty())
        m.texture = image_texture(scene, file, images, f.diffuse_map, false, f.diffuse_uv);
    m.vertex_colored = f.vertex_colors;
    if (m.texture >= 0 || m.vertex_colored) m.textured_lobes = 1;  // the Lambert lobe, first
    if (!f.normal_map.empty()) {
        m.normal_map = image_texture(scene, file, images, f.normal_map, true, f.normal_uv);
        m.normal_scale = f.normal_scale;
    }
    if (f.mirror && !ks.is_black()) {
        m.bsdf.add(Lobe::mirror(ks, Fresnel{}));
    } else if (!ks.is_black() && f.exponent > 0.f) {
        m.bsdf.add(Lobe::phong(ks, f.exponent));
    }
    if (f.dielectric_specular && trans < 1.f && dielectric > 0.f && f.dielectric_weight > 0.f) {
        const RGB w{dielectric * (1.f - trans) * (spec >= 0 ? 1.f : f.dielectric_weight)};
        m.bsdf.add(smooth ? Lobe::mirror(w, glass) : Lobe::microfacet(w, ggx, glass));
        param(LobeParam::WeightComplement, 3, Material::Remap::None);
        trans_param(LobeParam::WeightComplement);
        spec_param(LobeParam::Weight, 1.f);
        alpha_param();
    }
    if (metal > 0.f) {
        // The base colour as a conductor's normal reflectance; a base colour texture tints it.
        const Fresnel fr = conductor_from_reflectance(f.diffuse);
        m.bsdf.add(smooth ? Lobe::mirror(RGB{metal}, fr) : Lobe::microfacet(RGB{metal}, ggx, fr));
        if (m.texture >= 0 || m.vertex_colored)
            m.textured_lobes |= uint8_t(1u << (m.bsdf.size() - 1));
        param(LobeParam::Weight, 3, Material::Remap::None);
        alpha_param();
    }
    if (trans > 0.f || tr >= 0) {
        // A solid dielectric of the material's index, tinted by the base colour, weighted by
        // the transmitting share.
        const float w = dielectric * (tr >= 0 ? 1.f : trans);
        m.bsdf.add(smooth ? Lobe::dielectric(f.ior, RGB{w}, f.diffuse * w)
                          : Lobe::rough_dielectric(f.ior, ggx, RGB{w}, f.diffuse * w));
        param(LobeParam::WeightComplement, 3, Material::Remap::None);
        trans_param(LobeParam::Weight);
        alpha_param();
    }
    if (f.clearcoat > 0.f) add_clearcoat(scene, f, file, images, m);
}

}  // namespace

uint32_t add_file_material(Scene& scene, const FileMaterial& f, const MeshFile& file,
                           std::map<std::string, uint32_t>& images) {
    Material m;
    m.type = MaterialType::Generic;
    m.name = f.name.empty() ? "file material" : f.name;
    m.emission = f.emission;
    if (!f.emission_map.empty()) {
        if (!f.emission_given && m.emission.is_black()) m.emission = RGB{1.f};
        m.emission_texture =
            image_texture(scene, file, images, f.emission_map, false, f.emission_uv);
    }
    if (f.alpha < 1.f || !f.alpha_map.empty()) {
        m.alpha = f.alpha;
        m.alpha_cutoff = f.alpha_cutoff;
        if (!f.alpha_map.empty()) {
            // glTF's map is the base colour image (sRGB colour, linear alpha) and cuts only by
            // an alpha channel; MTL's map_d is a linear float image.
            const bool colour = f.alpha_map == f.diffuse_map;
            const uint32_t im = file_image(scene, file, images, f.alpha_map, !colour);
            // (file_image decodes once: the texture reuses that image.)
            if (!colour || !scene.texture_images[im].alpha.empty())
                m.alpha_texture = image_texture(scene, file, images, f.alpha_map, !colour,
                                                colour ? f.diffuse_uv : UvMap{});
        }
    }
    m.ior = f.ior;
    if (!f.bump_map.empty()) add_bump_map(scene, f, file, images, m);
    if (f.glass) {
        m.bsdf.add(Lobe::dielectric(f.ior, RGB{1.f}, RGB{1.f}));
        m.base_color = RGB{0.f};
    } else {
        add_surface_lobes(scene, f, file, images, m);
    }
    scene.materials.push_back(m);
    return uint32_t(scene.materials.size() - 1);
}

}  // namespace foton
