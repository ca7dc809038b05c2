#pragma once
// What a glTF file holds beside its meshes and core materials: KHR_lights_punctual lights and
// perspective cameras at their nodes, and the material extensions foton's lobes can render
// (KHR_materials_transmission, KHR_materials_ior; the emissive strength is the reader's, with
// the emission). Problems
// throw std::invalid_argument; the glTF reader adds the file and the element.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "camera.h"
#include "engine/core/math.h"
#include "mesh_file.h"

namespace tinygltf {
class Model;
class Node;
struct Material;
struct Image;
class Value;
}  // namespace tinygltf

namespace foton {

// A node's local transform: its column-major matrix, or translation x rotation x scale.
Affine gltf_node_transform(const tinygltf::Node& n);

// Camera c of the model at a node placed by xf (looking along the node's -z, +y up),
// perspective or orthographic; empty for a type glTF does not define.
std::optional<ModelView> gltf_camera(const tinygltf::Model& g, int c, const Affine& xf);

// Light l of KHR_lights_punctual at a node placed by xf, into `out`: photometric values over
// 683 lm/W (candela to W/sr, lux to W/m^2, Blender's reading); a range is noted (foton's
// lights fall off by the inverse square).
void gltf_light(const tinygltf::Model& g, int l, const Affine& xf, FileLights& out,
                std::vector<std::string>& notes, const std::string& where);

// A node's camera (the file's view when it is the first perspective one; others noted) and
// KHR_lights_punctual light, placed by xf, into `out`.
void gltf_node_extras(const tinygltf::Model& g, const tinygltf::Node& n, const Affine& xf,
                      MeshFile& out, const std::string& where);

// The material extensions foton renders, into f; the others (but the emissive strength) are
// noted.
void gltf_material_extensions(const tinygltf::Material& gm, FileMaterial& f,
                              std::vector<std::string>& notes, const std::string& where);

// glTF's alphaMode into f: MASK cuts where the base colour's alpha (factor times the texture's
// alpha channel) is below alphaCutoff; BLEND lets that alpha's share of the light through
// (stochastically, as pbrt-v4's alpha); OPAQUE ignores it.
void gltf_alpha_mode(const tinygltf::Material& gm, FileMaterial& f);

// A texture reference's KHR_texture_transform (offset, rotation, scale) as foton's uv map
// (glTF's v runs down, foton's up); the identity without one. Its texCoord, when given,
// replaces `tex_coord` (the reference's own).
UvMap gltf_uv_map(const std::map<std::string, tinygltf::Value>& extensions, int& tex_coord);

// A material's textures read up to two uv sets (TEXCOORD_n), which its primitives then load
// as their first and second texture coordinates: the first texture's set is the material's
// first, another set its second; the slot (0 or 1) a texture reads is returned. A third set
// is noted (that texture reads the first).
uint8_t gltf_use_tex_coord(FileMaterial& f, int tex_coord, const std::string& texture,
                           std::vector<std::string>& notes, const std::string& where);

// A primitive's vertex indices as a triangle list: unchanged for mode 4 (TRIANGLES); mode 5
// (TRIANGLE_STRIP) and 6 (TRIANGLE_FAN) unrolled with the winding the spec gives, so every
// triangle faces the way the first does.
std::vector<uint32_t> gltf_triangle_list(std::vector<uint32_t> indices, int mode);

// Whether foton reads glTF extension `name`, and the list of those it reads.
bool gltf_extension_read(const std::string& name);
std::string gltf_extensions_read();

// A sampler's wrapS or wrapT: REPEAT, CLAMP_TO_EDGE or MIRRORED_REPEAT.
TextureWrap gltf_wrap(int mode);

// An image tinygltf decoded (8 or 16 bits, 1 to 4 channels) as linear RGB: sRGB-decoded unless
// `linear` (a normal map); grey images repeat their channel, alpha is kept (linear) unless it
// is 1 everywhere. `name` is kept as its path.
TextureImage gltf_decode_image(const tinygltf::Image& im, const std::string& name, bool linear);

// Why the external image `uri` was not read, from tinygltf's load warnings (the line naming it:
// missing, outside the model's folder, unreadable), else a plain statement.
std::string gltf_unread_image_reason(const std::string& load_warnings, const std::string& uri);

}  // namespace foton
