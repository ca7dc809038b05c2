#pragma once
// The light sources as the Monte Carlo integrators and the photon mapper see them: every
// emitter can (1) sample an incident direction at a shading point with its solid-angle pdf,
// for next event estimation, (2) give that pdf for a direction that a BSDF sample happened
// to hit it by, for multiple importance sampling, and (3) sample an emitted ray (position
// and direction, each with its pdf), for light tracing and photon emission. Emitters are
// chosen in proportion to their power.
//
// Point and spot lights fall off with the inverse square law here; the thesis' 1/(1 + a d^2)
// attenuation is a Whitted-model device and applies only to the `raytracer` integrator.
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "direction_projection.h"
#include "engine/core/math.h"
#include "engine/core/rgb.h"
#include "engine/core/sampler.h"
#include "environment_projection.h"
#include "light_bvh.h"
#include "light_selection.h"
#include "projection_map.h"
#include "scene.h"

namespace foton {

enum class EmitterType : uint8_t { Point, Spot, Directional, Rect, Sphere, Mesh, Environment };
const char* emitter_name(EmitterType t);

struct Emitter {
    EmitterType type = EmitterType::Point;
    Vec3 p;              // position, rectangle corner or sphere centre
    Vec3 n;              // rectangle normal, spot axis, or the direction directional light travels
    Vec3 e1, e2;         // rectangle edges
    float radius = 0.f;  // sphere
    float area = 0.f;    // rectangle, sphere, mesh
    float cos_inner = 1.f, cos_outer = 0.f;  // spot
    RGB value;  // radiance (area kinds), intensity (point, spot), irradiance (dir.)
    uint32_t geom = 0xffffffffu;  // the scene object that shows it (area kinds)
    uint32_t mesh = 0;            // Mesh: index into Scene::meshes
    std::vector<float> tri_cdf;   // Mesh: area CDF over its triangles
    bool solid_angle = true;      // Sphere: sample the cone it subtends (else its area)
    bool two_sided = false;       // area kinds: emit from both sides
    RGB power;                    // emitted flux
    // Area kinds: a texture on the emission (Material::emission_texture; -1: none). The
    // radiance at a point is `emission` times its value there; `value` holds emission times
    // the texture's mean, which the power and light selection go by.
    int32_t texture = -1;
    RGB emission;

    bool is_delta_position() const {
        return type == EmitterType::Point || type == EmitterType::Spot;
    }
    bool is_delta_direction() const { return type == EmitterType::Directional; }
    bool is_delta() const { return is_delta_position() || is_delta_direction(); }
    // At infinity: no point of it can be joined to the camera, and rays find it by missing.
    bool is_infinite() const {
        return type == EmitterType::Directional || type == EmitterType::Environment;
    }
    float spot_falloff(float cos_theta) const;
};

// A direction towards the light from a shading point.
struct LightSample {
    Vec3 wi;           // unit, from the shading point towards the light
    float dist = 0.f;  // to the sampled point (infinity for directional)
    RGB Li;            // incident radiance (intensity / d^2 for delta lights)
    float pdf = 0.f;   // solid angle density (1 for delta lights); selection not included
    Vec3 p_light;      // the sampled point on the light
    Vec3 n_light;      // its surface normal, facing p (area kinds; zero otherwise)
};

// An emitted ray.
struct EmissionSample {
    Vec3 p, dir;
    Vec3 n;               // surface normal at p (zero for point and spot lights)
    RGB Le;               // radiance (area), intensity (point, spot) or irradiance (directional)
    float pdf_pos = 1.f;  // area density (1 for delta positions)
    float pdf_dir = 1.f;  // solid angle density (1 for directional)
};

struct EmittedRay {
    uint32_t light = 0;
    float pmf = 1.f;  // probability of having chosen this light
    EmissionSample emission;
    Vec3 origin;  // emission.p, offset off an emitting surface along the chosen side
    RGB beta;     // Le |cos| / (pmf pdf_pos pdf_dir)
};

// A mesh emitter taken whole (a triangle by area within it), or a light that is not a mesh.
inline constexpr uint32_t kWholeEmitter = 0xffffffffu;

// The light next event estimation samples: an emitter, under bvh a triangle of it, and the
// probability of the choice.
struct LightPick {
    uint32_t light = 0;
    uint32_t tri = kWholeEmitter;
    float pmf = 0.f;
};

// Many receivers' picks at once (LightSet::pick_lanes), structure of arrays: u and the
// receivers' points and normals in, `out` back. Sized by resize, which pads to the SIMD
// width the light BVH's descent kernel reads.
struct LightPickLanes {
    std::vector<float> u, px, py, pz, nx, ny, nz, pmf;
    std::vector<uint32_t> light;
    std::vector<LightPick> out;
    explicit LightPickLanes(std::size_t n = 0) { resize(n); }
    void resize(std::size_t n);
    void put(std::size_t i, float ui, const Vec3& p, const Vec3& n) {
        u[i] = ui;
        px[i] = p.x;
        py[i] = p.y;
        pz[i] = p.z;
        nx[i] = n.x;
        ny[i] = n.y;
        nz[i] = n.z;
    }
};

class LightSet {
  public:
    LightSet() = default;
    // projection_maps: directional and environment lights emit only over the geometry
    // (projection_map.h, environment_projection.h).
    explicit LightSet(const Scene& scene, LightSelection selection = LightSelection::Power,
                      bool projection_maps = true);
    // Emitter i's projection map (empty: none; directional lights only).
    const ProjectionMap& projection_map(std::size_t i) const { return projection_[i]; }
    // The environment's projection maps (environment_projection.h), built when first asked
    // for (by emission: a path tracer never pays for them); null without an environment, with
    // projection maps off, or for a scene with no geometry.
    const EnvironmentProjection* environment_projection() const;
    // Point or spot light i's map of the directions towards geometry (direction_projection.h),
    // built when first asked for; null for other lights or with projection maps off.
    const DirectionProjection* direction_projection(std::size_t i) const;

    std::size_t size() const { return emitters_.size(); }
    bool empty() const { return emitters_.empty(); }
    const Emitter& emitter(std::size_t i) const { return emitters_[i]; }
    // Emitter index of a scene object, or -1 when it does not emit.
    int emitter_of(uint32_t geom) const {
        return geom < geom_to_emitter_.size() ? geom_to_emitter_[geom] : -1;
    }

    // Chooses an emitter in proportion to its power (where light paths start).
    uint32_t select(float u, float& pmf) const;
    float pmf(uint32_t i) const { return pmf_[i]; }

    // Next event estimation's choice of a light for the receiver at p with geometric normal
    // n (zero: none), by the set's selection. False when no light can reach p (bvh only).
    LightSelection selection() const { return selection_; }
    bool pick(float u, const Vec3& p, const Vec3& n, LightPick& out) const;
    // The probability that pick(., p, n) chooses emitter `light` and, under bvh, triangle
    // `tri` of a mesh (any other light ignores tri).
    float pick_pmf(uint32_t light, uint32_t tri, const Vec3& p, const Vec3& n) const;
    // pick for lanes.u[i], lanes' point and normal i, i < count, into lanes.out[i] (pmf 0:
    // none); the same picks, bit for bit, with the light BVH's SIMD descent.
    void pick_lanes(LightPickLanes& lanes, std::size_t count) const;
    // The solid-angle density with which next event estimation from p (normal n) samples
    // point q (normal nq) of emitter `light`, found on triangle `tri`, the pick included:
    // what a BSDF sample that hit the light is weighed against.
    float nee_pdf(uint32_t light, uint32_t tri, const Vec3& p, const Vec3& n, const Vec3& q,
                  const Vec3& nq) const;
    // The same for a direction wi on the environment seen from p.
    float nee_environment_pdf(const Vec3& p, const Vec3& wi) const;

    // Samples a direction from `p` towards emitter i (only its triangle `tri` when one is
    // given); u and uc are uniform. False when the light cannot reach p (behind a one-sided
    // emitter, outside a spot cone, ...).
    bool sample_li(uint32_t i, const Vec3& p, Point2 u, float uc, LightSample& s,
                   uint32_t tri = kWholeEmitter) const;
    // Solid-angle density with which sample_li would have produced the point `q` (normal nq
    // on the emitting side) seen from `p`.
    float pdf_li(uint32_t i, const Vec3& p, const Vec3& q, const Vec3& nq,
                 uint32_t tri = kWholeEmitter) const;
    // The environment's emitter index (-1 without one), and the solid-angle density with
    // which light paths leave it along -wi, the light's selection included (the bidirectional
    // integrators weigh both a camera path's escape and an emitted ray by it: without a
    // portal it is also sample_li's density from any point; with one they refuse the scene).
    int environment() const { return environment_; }
    float environment_pdf(const Vec3& wi) const;
    // Samples an emitted ray: position with u_pos (and uc for the triangle of a mesh),
    // direction with u_dir.
    bool sample_le(uint32_t i, Point2 u_pos, Point2 u_dir, float uc, EmissionSample& s) const;
    // The densities with which sample_le would emit from point q (normal nq, on the emitting
    // side for area kinds) in direction `dir`: area density of the position (1 for delta
    // positions; the disc's for light from infinity) and solid-angle density of the
    // direction (1 for directional). For an environment q is ignored and `dir` is the
    // direction the light travels. What bidirectional MIS weighs a light vertex by.
    void pdf_le(uint32_t i, const Vec3& nq, const Vec3& dir, float& pdf_pos, float& pdf_dir) const;
    // The triangle of mesh emitter e that uc chooses by area (as sample_li does without a
    // given triangle), and a triangle's area in the world (e's whole area for kWholeEmitter).
    uint32_t triangle_by_area(const Emitter& e, float uc) const;
    float triangle_area(const Emitter& e, uint32_t tri) const;
    // The scene's bounding sphere (what light from infinity is emitted across).
    float scene_radius() const { return radius_; }
    // The start of a light path or photon: an emitter chosen by power with u_select, its
    // emitted ray, the ray's origin pushed off an emitting surface, and the path throughput
    // Le |cos| / (pmf pdf_pos pdf_dir). False when the sample carries no light.
    bool sample_ray(float u_select, Point2 u_pos, Point2 u_dir, float uc, EmittedRay& r) const;

  private:
    // bvh: the pick of a light at infinity when u falls in their share (else u rescaled to
    // the tree's share, as the descent takes it), and the tree's pick of primitive `prim`.
    bool pick_infinite(float& u, LightPick& out) const;
    LightPick tree_pick(uint32_t prim, float pmf) const;
    // A point uniform over the area of a rectangle, sphere or mesh emitter (or one triangle of
    // it), with the geometry's own normal there (u, and uc for a mesh's triangle), and the
    // area it is uniform over; `le`: the radiance emitted there.
    float sample_area_point(const Emitter& e, Point2 u, float uc, Vec3& q, Vec3& n, RGB& le,
                            uint32_t tri = kWholeEmitter) const;
    // A textured emitter's radiance at texture coordinates uv.
    RGB textured_radiance(const Emitter& e, const TexPoint& at) const;
    // The light BVH's primitives and tree (light_pick.cpp).
    void build_bvh();

    const Scene* scene_ = nullptr;
    std::vector<Emitter> emitters_;
    std::vector<float> pmf_, cdf_;
    std::vector<int> geom_to_emitter_;
    int environment_ = -1;
    LightSelection selection_ = LightSelection::Power;
    // bvh: the tree over the lights not at infinity, each emitter's first primitive there (a
    // mesh has one per triangle), the lights at infinity and the chance of picking one.
    LightBvh bvh_;
    std::vector<uint32_t> first_prim_;
    std::vector<uint32_t> prim_emitter_, prim_tri_;
    std::vector<uint32_t> infinite_;
    float p_infinite_ = 0.f;
    Vec3 center_;
    float radius_ = 0.f;  // bounding sphere of the scene, for directional emission
    std::vector<ProjectionMap> projection_;  // by emitter
    // Maps built on first use (call_once), shared by copies of the set.
    template <class Maps>
    struct Lazy {
        std::once_flag once;
        Maps maps;
    };
    std::shared_ptr<Lazy<EnvironmentProjection>> environment_projection_;
    std::vector<std::shared_ptr<Lazy<DirectionProjection>>> direction_projection_;  // by emitter
};

}  // namespace foton
