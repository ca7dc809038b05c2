#pragma once
// Mesh files with their materials: OBJ (+ MTL), PLY and glTF 2.0 read into one form, so
// that the XML loader places any of them the same way. A file's materials are described as
// FileMaterial (what the formats share: a diffuse colour or texture, a Phong highlight, a
// mirror or glass, glTF's metallic-roughness, emission) and become foton materials through
// add_file_material. What a file says that foton does not render is kept as a note
// ("file:line: what"), shown like the pbrt importer's warnings: never silently dropped.
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "camera.h"
#include "engine/core/rgb.h"
#include "light.h"
#include "mesh.h"
#include "texture.h"

namespace foton {

struct Scene;

struct FileMaterial {
    std::string name;
    RGB diffuse{0.8f};         // MTL Kd, glTF baseColorFactor
    std::string diffuse_map;   // an image file (resolved path) multiplying `diffuse`
    std::string normal_map;    // a tangent-space normal map (resolved path or embedded key)
    float normal_scale = 1.f;  // glTF normalTexture.scale: the map's x and y multiplied by it
    // glTF: a primitive using it has COLOR_0, which multiplies the base colour.
    bool vertex_colors = false;
    // glTF: the uv set (TEXCOORD_n) its textures read, which its primitives load as their
    // texture coordinates; -1: it has no texture.
    int tex_coord = -1;
    int tex_coord2 = -1;  // the second set some of its textures read (-1: none)
    // MTL's map_Bump (or bump): a height map, its grey values times `bump_multiplier` (-bm)
    // in scene units, or the tangent-space normal map many exporters write there; which of
    // the two is read off its texels (add_file_material).
    std::string bump_map;
    float bump_multiplier = 1.f;
    // Each map's uv transform (MTL's -s and -o on map_Kd, glTF's KHR_texture_transform).
    UvMap diffuse_uv, normal_uv, metallic_roughness_uv, emission_uv;
    RGB specular{0.f};  // MTL Ks: a Phong highlight of exponent Ns, or the mirror's colour
    float exponent = 0.f;
    float metallic = 0.f, roughness = 1.f;  // glTF metallic-roughness
    // glTF's metallicRoughnessTexture (read linearly): green scales roughness, blue metallic.
    std::string metallic_roughness_map;
    // glTF's dielectric: a GGX reflection of Fresnel index `ior` beside the diffuse part.
    bool dielectric_specular = false;
    // KHR_materials_specular: the reflection's strength and its normal-incidence tint (with a
    // tint, Schlick's Fresnel from min(F0(ior) x tint, 1), as the extension defines it).
    float dielectric_weight = 1.f;
    RGB dielectric_tint{1.f};
    // Its strength texture's alpha times dielectric_weight, per hit (glTF's specularTexture;
    // the texture index until the loader resolves the image, -1: none).
    std::string specular_map;
    UvMap specular_uv;
    int specular_texture = -1;
    bool mirror = false;       // MTL illum 3, 5
    bool glass = false;        // MTL illum 4, 6, 7, 9
    float ior = 1.5f;          // MTL Ni, glTF KHR_materials_ior
    float transmission = 0.f;  // glTF KHR_materials_transmission
    // Its texture's red channel times `transmission`, per hit (read linearly; the glTF
    // texture index until the loader resolves the image, -1: none).
    std::string transmission_map;
    UvMap transmission_uv;
    int transmission_texture = -1;
    // glTF KHR_materials_clearcoat: a clear dielectric coat (index 1.5) of this strength over
    // everything else, GGX of alpha = clearcoat_roughness^2.
    float clearcoat = 0.f, clearcoat_roughness = 0.f;
    // Its textures (read linearly): the red channel of clearcoat_map times clearcoat, the green
    // of clearcoat_roughness_map times clearcoat_roughness, per hit. glTF's texture indices
    // until the loader resolves them to images (-1: none).
    std::string clearcoat_map, clearcoat_roughness_map;
    UvMap clearcoat_uv, clearcoat_roughness_uv;
    int clearcoat_texture = -1, clearcoat_roughness_texture = -1;
    RGB emission{0.f};         // MTL Ke, glTF emissiveFactor
    std::string emission_map;  // an image multiplying `emission` (MTL map_Ke, glTF emissiveTexture)
    // Cut-outs (Material::alpha): MTL d and map_d, glTF's base colour alpha under alphaMode
    // MASK (with its cutoff) or BLEND. The map's float value (its alpha channel, or the mean of
    // its channels) multiplies `alpha`; glTF's map is the base colour image, used only where
    // that image has an alpha channel.
    float alpha = 1.f;
    std::string alpha_map;
    float alpha_cutoff = -1.f;  // < 0: stochastic
    // MTL: whether Ke was given (a map_Ke without it emits the map itself, Ke = 1).
    bool emission_given = false;
};

struct MeshPart {
    TriangleMesh mesh;
    int material = -1;         // into MeshFile::materials; -1: the file gives none
    bool has_normals = false;  // vertex normals came from the file (or its faces, for OBJ with uv)
};

// glTF's KHR_lights_punctual, placed by its node (the file's space): photometric values over
// 683 lm/W (candela to W/sr, lux to W/m^2), as Blender's importer reads them.
struct FileLights {
    std::vector<PointLight> points;
    std::vector<SpotLight> spots;
    std::vector<DirectionalLight> directionals;
    bool empty() const { return points.empty() && spots.empty() && directionals.empty(); }
};

struct MeshFile {
    std::vector<MeshPart> parts;
    std::vector<FileMaterial> materials;
    FileLights lights;
    std::optional<ModelView> view;  // glTF's first perspective camera, in the file's space
    // Decoded images of glTF files that embed them (keyed by a name materials use as
    // diffuse_map); files on disk are decoded by add_file_material.
    std::map<std::string, TextureImage> embedded_images;
    std::vector<std::string> notes;
    std::size_t degenerate_skipped = 0;
};

// Reads a mesh file by its extension: .obj (with the MTL files it names), .ply, .gltf, .glb.
// Throws InputError naming the file (and line, where the format has lines).
MeshFile load_mesh_file(const std::string& path);

// The MTL materials of an OBJ file, by name (relative map paths resolved against the MTL
// file's directory). Throws InputError at the MTL's file:line.
std::map<std::string, FileMaterial> parse_mtl(const std::string& text, const std::string& name,
                                              const std::string& base_dir,
                                              std::vector<std::string>& notes);

// glTF 2.0, .gltf (JSON with its buffers and images) or .glb: every triangle primitive of the
// default scene's nodes, transformed to world space, one part per primitive.
MeshFile load_gltf(const std::string& path);
// The same from the file's bytes (`binary`: .glb), external buffers and images resolved
// against base_dir.
MeshFile parse_gltf(const std::string& bytes, const std::string& name, const std::string& base_dir,
                    bool binary);

// Adds `m` to the scene's materials (with its texture, images decoded once per file through
// `images`: path -> Scene::texture_images); returns its index.
uint32_t add_file_material(Scene& scene, const FileMaterial& m, const MeshFile& file,
                           std::map<std::string, uint32_t>& images);

}  // namespace foton
