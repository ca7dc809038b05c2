#pragma once
// The Whitted-model materials of the first thesis. Radiometrically the diffuse part is a
// true Lambertian BRDF (c_diffuse * base / pi) so that area lights given in radiance give the
// same direct light as a physically based renderer; the ambient term and the Phong lobe are
// the thesis' empirical additions.
#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "bsdf.h"
#include "engine/core/rgb.h"

namespace foton {

// The thesis' four Whitted materials, the pure emitter of <area> lights, and Generic for the
// physically based models of the photon-mapping thesis (lambert, oren_nayar, conductor,
// dielectric, microfacet, mix), which exist only as a BSDF.
enum class MaterialType { Matte, Phong, Reflective, Glass, Emitter, Generic };
const char* material_type_name(MaterialType t);

struct Material {
    MaterialType type = MaterialType::Matte;
    float c_ambient = 0.f;  // ambient coefficient (times base colour and ambient light)
    float c_diffuse = 1.f;  // diffuse coefficient
    RGB base_color{0.5f};
    float c_specular = 1.f;  // scales specular_color
    float exponent = 10.f;   // Phong exponent
    RGB specular_color{0.f};
    float c_reflective = 1.f;
    RGB reflective_color{0.f};
    float ior = 1.5f;
    RGB refraction_color{1.f};
    RGB emission{0.f};  // radiance leaving the front side (any material may emit)
    // A texture on the emission (into Scene::textures, -1: none): at a point, the radiance
    // is `emission` times its value there (glTF's emissiveTexture, MTL's map_Ke).
    int32_t emission_texture = -1;
    bool emitter_solid_angle = true;  // sphere emitters: sample by solid angle (else by area)
    bool emission_two_sided = false;  // emit from both sides (e.g. a furnace seen from inside)
    bool emits_towards(bool front_face) const {
        return !emission.is_black() && (front_face || emission_two_sided);
    }
    std::string name;  // the XML type, for `foton info`
    // A surface that is no surface (pbrt-v4's "interface" material): it only bounds media, and
    // rays pass it unchanged. Its bsdf is empty.
    bool is_interface = false;
    // A texture on the reflectance (into Scene::textures, -1: none): at a hit, the lobes in
    // `textured_lobes` (bit i: lobe i) and base_color are multiplied by its value there
    // (their stored colour holds the rest: mix weights, coat transmission).
    int32_t texture = -1;
    uint8_t textured_lobes = 0;
    // The same lobes are multiplied by the mesh's interpolated vertex colour (glTF's COLOR_0,
    // times the texture when there is one; white on meshes without colours).
    bool vertex_colored = false;
    // A normal map's tangent-space x and y are multiplied by this before normalising (glTF's
    // normalTexture.scale).
    float normal_scale = 1.f;
    // A tangent-space normal map (into Scene::textures, an image read linearly; -1: none):
    // at a hit, the shading normal becomes T x + B y + N z for the texel's (2 rgb - 1), with
    // N the interpolated normal, T the surface's dp/du made perpendicular to it and B = N x T
    // (pbrt-v4's and glTF's convention; surface_at).
    int32_t normal_map = -1;
    // Alpha cut-outs (pbrt-v4's shape `alpha`, glTF's alphaMode): a hit counts where the alpha
    // (`alpha` times the float texture `alpha_texture`'s value, -1: none) is at least 1,
    // never where it is 0, and in between where a hash of the ray falls below it (pbrt-v4's
    // stochastic test), or, with a cutoff (glTF's MASK), where alpha >= alpha_cutoff. Rays
    // pass cut-out points as if nothing were there, in every backend (AlphaIntersector).
    float alpha = 1.f;
    int32_t alpha_texture = -1;
    float alpha_cutoff = -1.f;  // < 0: the stochastic test
    bool cuts_out() const { return alpha < 1.f || alpha_texture >= 0; }
    // Light that enters through the surface scatters below it and leaves elsewhere (a
    // subsurface material: into Scene::subsurfaces, -1: none). Its bsdf is the boundary, a
    // dielectric of the medium's index; what it transmits goes into the BSSRDF.
    int32_t subsurface = -1;
    // Bump mapping: a displacement texture (into Scene::textures, read as a float in scene
    // units; -1: none). At a hit, the shading normal becomes that of the displaced surface
    // p + d(u, v) n, from finite differences of d along u and v (pbrt-v4's BumpMap). A
    // normal map, when the material has both, wins (as in pbrt-v4).
    int32_t bump = -1;
    // Roughness and weight textures: at a hit, each entry sets one parameter of one lobe to
    // its texture's value there (a float texture: the mean of its channels, or one channel).
    static constexpr int kMaxFloatParams = 12;
    enum class Remap : uint8_t {
        None,
        Sqrt,    // the texture holds pbrt's roughness: alpha = sqrt(value)
        Square,  // glTF's roughness: alpha = value^2
    };
    struct FloatParam {
        int32_t texture = -1;  // into Scene::textures
        uint8_t lobe = 0;
        LobeParam target = LobeParam::AlphaX;
        Remap remap = Remap::None;
        uint8_t channel = 0;  // 0: the channels' mean; 1, 2, 3: red, green, blue; 4: alpha
        float k = 1.f;        // WeightComplement: the lobe's weight is 1 - k v
    };
    std::array<FloatParam, kMaxFloatParams> float_params{};
    uint8_t num_float_params = 0;
    // Adds a roughness texture; false when the material holds kMaxFloatParams already.
    bool add_float_param(const FloatParam& p) {
        if (num_float_params == kMaxFloatParams) return false;
        float_params[num_float_params++] = p;
        return true;
    }
    // The material changes over the surface (a colour, roughness or emission texture, or a
    // hair fibre's offset h, read from v).
    bool varies() const {
        return texture >= 0 || vertex_colored || num_float_params > 0 || emission_texture >= 0 ||
               bsdf.has_hair();
    }
    // The shading normal is a texture's (normal or bump map).
    bool perturbs_normal() const { return normal_map >= 0 || bump >= 0; }
    bool needs_uv() const { return varies() || perturbs_normal(); }
    // The BSDF's frame must follow the surface's dp/du (an anisotropic lobe, or roughness
    // textures, which may make one).
    bool needs_tangent() const { return num_float_params > 0 || bsdf.anisotropic(); }

    // The physically based model the Monte Carlo integrators use (also for the thesis'
    // types: matte = Lambert, phong = Lambert + modified Phong, reflective = + mirror,
    // glass = dielectric). Built by the loader.
    Bsdf bsdf;

    bool is_specular() const {
        return type == MaterialType::Reflective || type == MaterialType::Glass;
    }
};

// Material m with its BSDF regularized (pbrt-v4's regularize), in `scratch` (which may hold m
// already, a textured copy).
inline const Material& regularized_material(const Material& m, std::optional<Material>& scratch) {
    if (!scratch || &*scratch != &m) scratch = m;
    scratch->bsdf = m.bsdf.regularized();
    return *scratch;
}

}  // namespace foton
