#pragma once
// Reflectance models of the photon-mapping thesis (appendix A) as lobes, and a BSDF as a
// weighted set of lobes (plastic = Lambert + microfacet, the thesis' Phong = Lambert +
// Phong lobe, ...). Materials have no textures, so a material's BSDF is built once at load
// time and used at every hit in the local shading frame: z = shading normal on the side the
// ray came from, so wo.z > 0 for the incoming direction (up to shading-normal leaning).
//
// Conventions (pbrt's): f(wo, wi) with wo towards the viewer (the camera, or the previous
// vertex of a camera path) and wi towards the light. Sampling returns wi, the value f and
// the solid-angle pdf; for a delta lobe f carries the 1/|cos| so that f |cos| / pdf is the
// path weight as for every other lobe, and eval() ignores delta lobes.
#include <array>
#include <cstdint>

#include "coat_layer.h"
#include "engine/core/dispersion.h"
#include "engine/core/math.h"
#include "engine/core/rgb.h"
#include "engine/core/sampler.h"
#include "hair_fiber.h"
#include "microfacet.h"

namespace foton {

struct Wavelengths;   // core/spectrum.h
struct MeasuredBrdf;  // measured_brdf.h

// Radiance flows against the sampling direction in camera paths, importance in light
// paths; refraction scales the two differently (Veach's adjoint BSDF).
enum class Transport : uint8_t { Radiance, Importance };

struct BsdfContext {
    bool front = true;  // the ray arrived on the side the geometry's normal points to
    Transport mode = Transport::Radiance;
};

enum LobeFlags : uint8_t {
    kDiffuse = 1,
    kGlossy = 2,
    kSpecular = 4,  // a delta lobe
    kReflection = 8,
    kTransmission = 16,
};

// Schlick: the ray-tracing thesis' approximation (3.2.2), F0 + (1 - F0) (1 - cos)^5, with F0
// a dielectric's ((n - 1) / (n + 1))^2 or a conductor's exact normal-incidence reflectance.
enum class FresnelKind : uint8_t { None, Dielectric, Conductor, Schlick };

struct Fresnel {
    FresnelKind kind = FresnelKind::None;
    float ior = 1.5f;      // dielectric
    RGB eta{1.f}, k{0.f};  // conductor, per channel
    RGB f0{0.04f};         // Schlick's reflectance at normal incidence
    RGB eval(float cos_i) const;
    static Fresnel schlick(const RGB& f0);
};

enum class LobeType : uint8_t {
    Lambert,
    OrenNayar,
    Phong,                // modified, energy-conserving Phong (Lafortune & Willems)
    Mirror,               // specular reflection with an optional (conductor) Fresnel
    Dielectric,           // specular reflection + transmission with dielectric Fresnel, TIR
    Microfacet,           // Torrance–Sparrow: F D G / (4 cos_o cos_i)
    LambertTransmission,  // diffuse transmission: reflectance/pi on the side opposite wo
                          // (pbrt-v4's diffusetransmission with a Lambert lobe beside it)
    RoughDielectric,      // Walter et al. 2007: a rough dielectric interface, microfacet reflection
                          // and transmission (rough_dielectric.cpp)
    Coated,               // a dielectric coat over a Lambertian or conductor base, evaluated by
                          // random walks through the layer (pbrt-v4's LayeredBxDF; coated.cpp)
    Hair,                 // Chiang et al. 2016's fibre scattering (pbrt-v4's hair; hair.cpp)
    ThinDielectric,       // a thin slab (a window pane): specular reflection with the slab's
                          // inter-reflections, transmission straight through (pbrt-v4's
                          // thindielectric; thin_dielectric.cpp)
    Measured,             // a measured BRDF of the RGL database (pbrt-v4's "measured";
                          // measured_brdf.h)
    SubsurfaceExit,       // where light leaves a subsurface material (the BSSRDF's directional
                          // part, pbrt-v4's NormalizedFresnelBxDF): (1 - F(wi)) / (c pi) with c
                          // normalising it to reflect everything, times eta^2 for radiance
};

struct Lobe {
    LobeType type = LobeType::Lambert;
    RGB color{0.f};                // reflectance / tint (includes the material's mix weight)
    RGB transmit{0.f};             // dielectric transmission tint
    float on_a = 1.f, on_b = 0.f;  // Oren–Nayar A, B from sigma
    float exponent = 1.f;          // Phong
    Fresnel fresnel;
    MicrofacetDistribution dist;
    CoatLayer coat;  // Coated: the coat and the medium under it (the base is color, fresnel, dist)
    HairFiber hair;  // Hair (color: the mix weight)
    // Measured (color: the mix weight): the data (the scene owns it) and, on a spectral path,
    // the wavelengths its spectra are read at (0: read as RGB).
    const MeasuredBrdf* measured = nullptr;
    float lambda[3] = {0.f, 0.f, 0.f};
    // Dielectric, RoughDielectric, ThinDielectric: the index over wavelength of a dispersive
    // glass (fresnel.ior holds its d-line index, which RGB rendering uses; a spectral path
    // reads it at its hero wavelength and carries that one alone on, Bsdf::to_wavelengths).
    Dispersion dispersion;

    uint8_t flags() const;
    // Its frame's orientation about the normal matters: roughness differing along x and y, or
    // a fibre (x along it).
    bool anisotropic() const;
    bool is_delta() const {
        return type == LobeType::Mirror || type == LobeType::Dielectric ||
               type == LobeType::ThinDielectric || (type == LobeType::Coated && coat_is_delta());
    }
    // f and pdf are Monte Carlo estimates (a Coated lobe); a mixture holding one samples by
    // lobe selection (Bsdf::sample).
    bool is_stochastic() const { return type == LobeType::Coated; }
    // Every path through a Coated lobe is specular: smooth coat, mirror base, no medium.
    bool coat_is_delta() const {
        return coat.coat_smooth && coat.base == CoatBase::Conductor && coat.base_smooth &&
               coat.albedo.is_black();
    }

    static Lobe lambert(const RGB& r);
    static Lobe oren_nayar(const RGB& r, float sigma_radians);
    static Lobe phong(const RGB& ks, float exponent);
    static Lobe mirror(const RGB& r, const Fresnel& f);
    static Lobe dielectric(float ior, const RGB& reflect, const RGB& transmit);
    // A thin slab of index ior: light passes through undeviated or reflects.
    static Lobe thin_dielectric(float ior, const RGB& reflect, const RGB& transmit);
    static Lobe microfacet(const RGB& tint, const MicrofacetDistribution& d, const Fresnel& f);
    // Diffuse transmission of tint t (paper, leaves, lamp shades).
    static Lobe lambert_transmission(const RGB& t);
    // A rough interface of index ior (Trowbridge–Reitz `d`), tinted as a dielectric.
    static Lobe rough_dielectric(float ior, const MicrofacetDistribution& d, const RGB& reflect,
                                 const RGB& transmit);
    // pbrt-v4's coateddiffuse: a coat `c` over a Lambertian base of reflectance r.
    static Lobe coated_diffuse(const RGB& r, const CoatLayer& c);
    // pbrt-v4's coatedconductor: a coat over a conductor of Fresnel `f` (eta and k relative to
    // the coat), smooth or of roughness `d`.
    static Lobe coated_conductor(const Fresnel& f, bool smooth, const MicrofacetDistribution& d,
                                 const CoatLayer& c);
    // The BSSRDF's directional part at an exit point of a material of index eta.
    static Lobe subsurface_exit(float eta);
    // pbrt-v4's hair: a fibre of these parameters (its offset h set per hit).
    static Lobe hair_fiber(const HairFiber& h);
    // pbrt-v4's measured: the BRDF of a .bsdf file.
    static Lobe measured_brdf(const MeasuredBrdf* b);
};

// What a texture sets on one lobe at a surface point (Material::float_params): a microfacet
// alpha of the lobe's own distribution (a microfacet conductor, a rough dielectric, a coated
// lobe's conductor base) or of a coated lobe's coat, along x or y; or the lobe's weight, as v
// or 1 - v (glTF's metallic texture shares a surface between a metal and a dielectric).
enum class LobeParam : uint8_t {
    AlphaX,
    AlphaY,
    Alpha,  // both
    CoatAlphaX,
    CoatAlphaY,
    Weight,
    WeightComplement,
    HairOffset,  // a hair lobe's h, -1 to 1 across the fibre
};

struct BsdfSample {
    Vec3 wi;
    RGB f;
    float pdf = 0.f;
    uint8_t flags = 0;
    // A refraction's relative index eta_t / eta_i (1 otherwise): radiance through it is
    // scaled by 1 / eta^2, which Russian roulette must not mistake for absorption.
    float eta = 1.f;
    bool is_delta() const { return (flags & kSpecular) != 0; }
};

class Bsdf {
  public:
    static constexpr int kMaxLobes = 8;

    // Adds a lobe; returns false when the BSDF is full.
    bool add(const Lobe& lobe);
    int size() const { return n_; }
    const Lobe& lobe(int i) const { return lobes_[std::size_t(i)]; }
    // Lobe i's sampling weight (sample() picks lobes in proportion to these).
    float weight(int i) const { return weight_[std::size_t(i)]; }
    bool empty() const { return n_ == 0; }
    // Some lobe's roughness differs along x and y: its orientation is the frame's.
    bool anisotropic() const { return anisotropic_; }
    // Some lobe is a hair fibre (its offset h is set per hit).
    bool has_hair() const {
        for (int i = 0; i < n_; ++i)
            if (lobes_[std::size_t(i)].type == LobeType::Hair) return true;
        return false;
    }
    bool has_non_delta() const { return (flags_ & (kDiffuse | kGlossy)) != 0; }
    // Some non-delta lobe transmits (a rough dielectric): light reaches the vertex from
    // behind its surface by other routes than a sampled delta refraction.
    bool transmits_non_delta() const { return transmits_non_delta_; }
    // Whether unit direction w leaving a vertex with geometric normal ng (facing the arriving
    // ray) can carry light to or from it: on ng's side, or behind when a non-delta lobe
    // transmits. A light sample, a camera connection or a photon on the other side counts.
    bool side_allowed(const Vec3& w, const Vec3& ng) const {
        const float c = dot(w, ng);
        return c > 0.f || (c < 0.f && transmits_non_delta_);
    }
    bool has_delta() const { return (flags_ & kSpecular) != 0; }
    uint8_t flags() const { return flags_; }
    // When every non-delta lobe is Lambertian: true, and their summed reflectance (the
    // radiance they reflect is rho / pi times the irradiance).
    bool lambert_albedo(RGB& rho) const {
        rho = RGB{0.f};
        for (int i = 0; i < n_; ++i) {
            const Lobe& l = lobes_[std::size_t(i)];
            if (l.is_delta()) continue;
            if (l.type != LobeType::Lambert) return false;
            rho += l.color;
        }
        return true;
    }
    // Probability that sample() picks a lobe with any of `only`'s flags.
    float selection_probability(uint8_t only) const {
        const float all = weight_sum(0xff);
        return all > 0.f ? weight_sum(only) / all : 0.f;
    }
    // A direction-independent estimate of the albedo: the largest channel of the lobes'
    // summed tints (a dielectric's larger of reflection and transmission), at most 1. What
    // the bidirectional integrators continue a subpath with (Russian roulette whose
    // probability depends on the vertex alone, so both subpaths' MIS sums can include it).
    float continuation() const;
    // Scales every lobe's colour (for mixtures), or lobe i's.
    void scale(float w);
    void scale_lobe(int i, float w);
    // A copy whose lobes in `lobes` (bit i: lobe i) have their colour multiplied by `t`:
    // a textured reflectance at one surface point. Sampling weights follow the colours.
    Bsdf with_texture(uint8_t lobes, const RGB& t) const;
    // Sets parameter `target` of lobe i to v (a texture's value at a surface point).
    void set_param(int i, LobeParam target, float v);
    // The BSDF at a spectral path's three wavelengths (spectral_bsdf.cpp): every lobe's RGB
    // parameters upsampled and read there (tints and reflectances as reflectance spectra, a
    // conductor's eta and k and a fibre's absorption as unbounded ones). The sampling weights
    // stay the RGB ones, so sample() and pdf() agree as before. A dispersive glass takes its
    // index at the hero wavelength, lambda[0] (the path then carries that one alone on:
    // disperses()).
    void to_wavelengths(const Wavelengths& w);
    // pbrt-v4's regularisation (bsdf_regularize.cpp): specular reflection and refraction made
    // Trowbridge–Reitz lobes of alpha 0.1, rough ones below alpha 0.3 doubled (at least 0.1,
    // at most 0.3), a coat's interfaces alike; for the vertices after a path's first
    // non-specular one, where near-specular paths would only be found by chance.
    Bsdf regularized() const;
    // Some lobe is a dispersive glass: a spectral path meeting it keeps its hero wavelength
    // only, as one direction cannot refract every wavelength (pbrt-v4's TerminateSecondary).
    bool disperses() const { return disperses_; }

    // Sum of the non-delta lobes.
    RGB f(const Vec3& wo, const Vec3& wi, const BsdfContext& ctx) const;
    float pdf(const Vec3& wo, const Vec3& wi, const BsdfContext& ctx) const;
    // Picks a lobe with uc by its sampling weight, samples it with u. `only` restricts the
    // choice to lobes with any of these flags (the distributed ray tracer samples only
    // glossy and specular lobes); the pdf is then that of the restricted mixture.
    bool sample(const Vec3& wo, float uc, Point2 u, const BsdfContext& ctx, BsdfSample& s,
                uint8_t only = 0xff) const;
    // Same restriction for f and pdf (with the restricted selection probabilities).
    RGB f_restricted(const Vec3& wo, const Vec3& wi, const BsdfContext& ctx, uint8_t only) const;
    float pdf_restricted(const Vec3& wo, const Vec3& wi, const BsdfContext& ctx,
                         uint8_t only) const;

    // The deterministic directions of the delta lobes and their weights f |cos| / 1, for
    // Whitted-style branching: up to two per dielectric lobe, one per mirror.
    int specular_directions(const Vec3& wo, const BsdfContext& ctx, Vec3* dirs, RGB* weights,
                            int max_out) const;

  private:
    float weight_sum(uint8_t only) const;
    std::array<Lobe, kMaxLobes> lobes_{};
    std::array<float, kMaxLobes> weight_{};  // sampling weight of each lobe
    int n_ = 0;
    uint8_t flags_ = 0;
    bool transmits_non_delta_ = false;
    bool stochastic_ = false;  // some lobe is_stochastic()
    bool anisotropic_ = false;
    bool disperses_ = false;  // some lobe's dispersion.disperses()
};

// Single-lobe operations (exposed for the tests' chi-square and albedo checks).
RGB lobe_f(const Lobe& l, const Vec3& wo, const Vec3& wi, const BsdfContext& ctx);
float lobe_pdf(const Lobe& l, const Vec3& wo, const Vec3& wi, const BsdfContext& ctx);
bool lobe_sample(const Lobe& l, const Vec3& wo, float uc, Point2 u, const BsdfContext& ctx,
                 BsdfSample& s);
// The same for a RoughDielectric lobe (rough_dielectric.cpp).
RGB rough_dielectric_f(const Lobe& l, const Vec3& wo, const Vec3& wi, const BsdfContext& ctx);
// `only` restricts pdf and sampling to reflection or transmission (kReflection, kTransmission).
float rough_dielectric_pdf(const Lobe& l, const Vec3& wo, const Vec3& wi, const BsdfContext& ctx,
                           uint8_t only = kReflection | kTransmission);
bool rough_dielectric_sample(const Lobe& l, const Vec3& wo, float uc, Point2 u,
                             const BsdfContext& ctx, BsdfSample& s,
                             uint8_t only = kReflection | kTransmission);
// The same for a Coated lobe (coated.cpp): f and pdf are estimates from random walks through
// the layer whose random numbers are a hash of the directions (so f(wo, wi) is a function);
// sample's f and pdf are the sampled walk's own, whose ratio is the weight to use.
RGB coated_f(const Lobe& l, const Vec3& wo, const Vec3& wi, const BsdfContext& ctx);
float coated_pdf(const Lobe& l, const Vec3& wo, const Vec3& wi, const BsdfContext& ctx);
bool coated_sample(const Lobe& l, const Vec3& wo, float uc, Point2 u, const BsdfContext& ctx,
                   BsdfSample& s);
// The same for a Hair lobe (hair.cpp): its frame's x runs along the fibre. lobe_f and
// lobe_sample give importance transport the adjoint f(wi, wo): the fibre is not reciprocal.
RGB hair_f(const Lobe& l, const Vec3& wo, const Vec3& wi);
// What importance transport (light paths) reads: f(wi, wo) times cos(theta_i) / |wi.z|, the
// width the fibre shows towards wi over that of the ribbon the light path met, which faces wo.
RGB hair_adjoint_f(const Lobe& l, const Vec3& wo, const Vec3& wi);
float hair_pdf(const Lobe& l, const Vec3& wo, const Vec3& wi);
bool hair_sample(const Lobe& l, const Vec3& wo, float uc, Point2 u, BsdfSample& s,
                 Transport mode = Transport::Radiance);
// A Measured lobe (measured_brdf.cpp).
RGB measured_f(const Lobe& l, const Vec3& wo, const Vec3& wi);
float measured_pdf(const Lobe& l, const Vec3& wo, const Vec3& wi);
bool measured_sample(const Lobe& l, const Vec3& wo, Point2 u, BsdfSample& s);
// A ThinDielectric lobe (thin_dielectric.cpp): the slab's reflectance R at |cos theta| (the
// interface's Fresnel R0 plus every inner reflection, T0^2 R0 / (1 - R0^2)); it transmits 1 - R.
float thin_dielectric_reflectance(float cos_theta, float ior);
bool thin_dielectric_sample(const Lobe& l, const Vec3& wo, float uc, BsdfSample& s);
// A coated lobe's reflectance along the mirror direction of a smooth coat (the part f leaves
// out as a delta): the coat's own Fresnel reflection, or, when the whole stack is specular,
// every bounce between the coat and the mirror base in closed form.
RGB coated_mirror_weight(const Lobe& l, const Vec3& wo);

}  // namespace foton
