#include "light_set.h"

#include <algorithm>
#include <cmath>

#include "engine/core/warp.h"

namespace foton {

namespace {
// 1 - cos(theta_max) of the cone a sphere subtends, from sin^2(theta_max) = r^2 / d^2, as
// sin^2 / (1 + cos): exact for small cones, where 1 - cos cancels. Sampling and pdf_li share it.
float cone_one_minus_cos(float sin2_max) {
    return sin2_max / (1.f + std::sqrt(std::max(0.f, 1.f - sin2_max)));
}
}  // namespace

const char* emitter_name(EmitterType t) {
    switch (t) {
        case EmitterType::Point:
            return "point";
        case EmitterType::Spot:
            return "spot";
        case EmitterType::Directional:
            return "directional";
        case EmitterType::Rect:
            return "rectangle";
        case EmitterType::Sphere:
            return "sphere";
        case EmitterType::Mesh:
            return "mesh";
        case EmitterType::Environment:
            return "environment";
    }
    return "?";
}

float Emitter::spot_falloff(float c) const {
    if (c <= cos_outer) return 0.f;
    if (c >= cos_inner) return 1.f;
    const float x = (c - cos_outer) / (cos_inner - cos_outer);
    return x * x * (3.f - 2.f * x);
}

LightSet::LightSet(const Scene& scene, LightSelection selection, bool projection_maps)
    : scene_(&scene), selection_(selection) {
    const Bounds3 bounds = scene.bounds();
    center_ = bounds.center();
    radius_ = 0.5f * length(bounds.diagonal());
    if (!(radius_ > 0.f)) radius_ = 1.f;
    geom_to_emitter_.assign(scene.objects.size(), -1);
    const Lights& L = scene.lights;
    for (const PointLight& pl : L.points) {
        Emitter e;
        e.type = EmitterType::Point;
        e.p = pl.position;
        e.value = pl.intensity;
        e.power = pl.intensity * (4.f * kPi);
        emitters_.push_back(e);
    }
    for (const SpotLight& sl : L.spots) {
        Emitter e;
        e.type = EmitterType::Spot;
        e.p = sl.position;
        e.n = sl.direction;
        e.value = sl.intensity;
        e.cos_inner = sl.cos_inner;
        e.cos_outer = sl.cos_outer;
        // Full intensity to the inner cone, smoothstep to the outer: halfway is close enough
        // for choosing lights by power.
        e.power = sl.intensity * (2.f * kPi * (1.f - 0.5f * (sl.cos_inner + sl.cos_outer)));
        emitters_.push_back(e);
    }
    for (const DirectionalLight& dl : L.directionals) {
        Emitter e;
        e.type = EmitterType::Directional;
        e.n = dl.direction;
        e.value = dl.radiance;
        e.power = dl.radiance * (kPi * radius_ * radius_);
        emitters_.push_back(e);
    }
    for (const AreaLight& al : L.areas) {
        Emitter e;
        e.type = EmitterType::Rect;
        e.p = al.corner;
        e.e1 = al.edge1;
        e.e2 = al.edge2;
        e.n = al.normal;
        e.area = al.area;
        e.value = al.radiance;
        e.geom = al.geometry;
        e.power = al.radiance * (kPi * al.area);
        if (e.geom < geom_to_emitter_.size()) geom_to_emitter_[e.geom] = int(emitters_.size());
        emitters_.push_back(e);
    }
    for (uint32_t g = 0; g < scene.objects.size(); ++g) {
        const Object& o = scene.objects[g];
        const Material& m = scene.materials[o.material];
        if (m.emission.is_black() || m.type == MaterialType::Emitter) continue;
        Emitter e;
        e.value = e.emission = m.emission;
        if (m.emission_texture >= 0) {
            e.texture = m.emission_texture;
            e.value = m.emission *
                      scene.textures[std::size_t(m.emission_texture)].mean(scene.texture_images);
            if (e.value.is_black()) continue;
        }
        e.geom = g;
        e.two_sided = m.emission_two_sided;
        if (o.kind == ObjectKind::Sphere) {
            const Sphere& s = scene.spheres[o.index];
            e.type = EmitterType::Sphere;
            e.p = s.center;
            e.radius = s.radius;
            e.area = 4.f * kPi * s.radius * s.radius;
            e.solid_angle = m.emitter_solid_angle;
        } else {
            const TriangleMesh& mesh = scene.meshes[o.index];
            e.type = EmitterType::Mesh;
            e.mesh = o.index;
            float acc = 0.f;
            e.tri_cdf.reserve(mesh.num_triangles());
            for (uint32_t t = 0; t < mesh.num_triangles(); ++t) {
                Vec3 p0, p1, p2;
                scene.world_corners(g, t, p0, p1, p2);
                acc += 0.5f * length(cross(p1 - p0, p2 - p0));
                e.tri_cdf.push_back(acc);
            }
            e.area = acc;
            if (!(acc > 0.f)) continue;
        }
        e.power = e.value * (kPi * e.area * (e.two_sided ? 2.f : 1.f));
        geom_to_emitter_[g] = int(emitters_.size());
        emitters_.push_back(std::move(e));
    }
    if (scene.environment) {
        Emitter e;
        e.type = EmitterType::Environment;
        e.power = scene.environment->integral() * (kPi * radius_ * radius_);
        environment_ = int(emitters_.size());
        emitters_.push_back(e);
        // Its power stays that through the whole disc: the selection (and next event
        // estimation's pick) does not change with the maps; its photons carry less each.
        if (projection_maps)
            environment_projection_ = std::make_shared<Lazy<EnvironmentProjection>>();
    }
    // Point and spot lights' maps, built on first emission.
    direction_projection_.resize(emitters_.size());
    for (std::size_t i = 0; i < emitters_.size() && projection_maps; ++i)
        if (emitters_[i].type == EmitterType::Point || emitters_[i].type == EmitterType::Spot)
            direction_projection_[i] = std::make_shared<Lazy<DirectionProjection>>();
    // A directional light's projection map, and its power then: what crosses the map's cells.
    projection_.resize(emitters_.size());
    for (std::size_t i = 0; i < emitters_.size() && projection_maps; ++i) {
        Emitter& e = emitters_[i];
        if (e.type != EmitterType::Directional) continue;
        const warp::Frame fr(e.n);
        projection_[i].build(scene, fr.s, fr.t, center_, radius_);
        if (!projection_[i].empty()) e.power = e.value * projection_[i].area();
    }
    // Selection by power (luminance); lights of zero power are never chosen.
    float total = 0.f;
    for (const Emitter& e : emitters_) total += std::max(0.f, e.power.luminance());
    for (const Emitter& e : emitters_) {
        const float p = total > 0.f ? std::max(0.f, e.power.luminance()) / total
                                    : 1.f / float(emitters_.size());
        pmf_.push_back(p);
        cdf_.push_back((cdf_.empty() ? 0.f : cdf_.back()) + p);
    }
    if (!cdf_.empty()) cdf_.back() = 1.f;
    if (selection_ == LightSelection::Bvh) build_bvh();
}

const EnvironmentProjection* LightSet::environment_projection() const {
    if (!environment_projection_) return nullptr;
    Lazy<EnvironmentProjection>& lazy = *environment_projection_;
    std::call_once(lazy.once, [&] { lazy.maps.build(*scene_, center_, radius_); });
    return lazy.maps.empty() ? nullptr : &lazy.maps;
}

const DirectionProjection* LightSet::direction_projection(std::size_t i) const {
    if (i >= direction_projection_.size() || !direction_projection_[i]) return nullptr;
    Lazy<DirectionProjection>& lazy = *direction_projection_[i];
    const Emitter& e = emitters_[i];
    std::call_once(lazy.once, [&] {
        lazy.maps.build(*scene_, e.p, e.n, e.type == EmitterType::Spot ? e.cos_outer : -2.f);
    });
    return lazy.maps.empty() ? nullptr : &lazy.maps;
}

uint32_t LightSet::select(float u, float& pmf) const {
    // The first step above u: a scan for a handful of lights (the usual scene), else a
    // binary search; the same index either way.
    std::size_t at = 0;
    if (cdf_.size() <= 8) {
        while (at < cdf_.size() && !(u < cdf_[at])) ++at;
    } else {
        at = std::size_t(std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin());
    }
    uint32_t i = uint32_t(std::min(at, cdf_.size() - 1));
    while (pmf_[i] == 0.f && i > 0) --i;  // u on a zero-width step
    pmf = pmf_[i];
    return i;
}

float LightSet::sample_area_point(const Emitter& e, Point2 u, float uc, Vec3& q, Vec3& n, RGB& le,
                                  uint32_t tri) const {
    le = e.value;
    if (e.type == EmitterType::Rect) {
        q = e.p + e.e1 * u.x + e.e2 * u.y;
        n = e.n;
        return e.area;
    }
    if (e.type == EmitterType::Sphere) {
        n = warp::uniform_sphere(u);
        q = e.p + n * e.radius;
        if (e.texture >= 0) le = textured_radiance(e, TexPoint{sphere_uv(n), q, n});
        return e.area;
    }
    const uint32_t t = tri == kWholeEmitter ? triangle_by_area(e, uc) : tri;
    Vec3 p0, p1, p2;
    scene_->world_corners(e.geom, t, p0, p1, p2);
    const Point2 b = warp::uniform_triangle(u);
    q = p0 * (1.f - b.x - b.y) + p1 * b.x + p2 * b.y;
    const Vec3 c = cross(p1 - p0, p2 - p0);
    n = normalize(c);
    if (e.texture >= 0) {
        // The triangle's texture coordinates at the point (pbrt's default without uv).
        Point2 t0, t1, t2;
        scene_->meshes[e.mesh].corner_uvs(t, t0, t1, t2,
                                          scene_->textures[std::size_t(e.texture)].uv.set);
        const float w = 1.f - b.x - b.y;
        le = textured_radiance(
            e, TexPoint{
                   {t0.x * w + t1.x * b.x + t2.x * b.y, t0.y * w + t1.y * b.x + t2.y * b.y}, q, n});
    }
    return tri == kWholeEmitter ? e.area : 0.5f * length(c);
}

RGB LightSet::textured_radiance(const Emitter& e, const TexPoint& at) const {
    return e.emission * scene_->textures[std::size_t(e.texture)].eval(scene_->texture_images, at);
}

uint32_t LightSet::triangle_by_area(const Emitter& e, float uc) const {
    const float target = uc * e.area;
    const auto it = std::upper_bound(e.tri_cdf.begin(), e.tri_cdf.end(), target);
    return uint32_t(
        std::min<std::ptrdiff_t>(it - e.tri_cdf.begin(), std::ptrdiff_t(e.tri_cdf.size()) - 1));
}

float LightSet::triangle_area(const Emitter& e, uint32_t tri) const {
    if (e.type != EmitterType::Mesh || tri == kWholeEmitter) return e.area;
    Vec3 p0, p1, p2;
    scene_->world_corners(e.geom, tri, p0, p1, p2);
    return 0.5f * length(cross(p1 - p0, p2 - p0));
}

bool LightSet::sample_li(uint32_t i, const Vec3& p, Point2 u, float uc, LightSample& s,
                         uint32_t tri) const {
    const Emitter& e = emitters_[i];
    switch (e.type) {
        case EmitterType::Point:
        case EmitterType::Spot: {
            const Vec3 to = e.p - p;
            const float d2 = length_squared(to);
            if (d2 == 0.f) return false;
            s.dist = std::sqrt(d2);
            s.wi = to / s.dist;
            s.p_light = e.p;
            s.pdf = 1.f;
            float f = 1.f;
            if (e.type == EmitterType::Spot) f = e.spot_falloff(dot(-s.wi, e.n));
            if (f == 0.f) return false;
            s.Li = e.value * (f / d2);
            return true;
        }
        case EmitterType::Environment: {
            s.wi = scene_->environment->sample(p, u, s.pdf);
            if (!(s.pdf > 0.f)) return false;
            s.dist = kInfinity;
            s.p_light = p + s.wi * (2.f * radius_);
            s.Li = scene_->environment->Le(p, s.wi);
            return !s.Li.is_black();
        }
        case EmitterType::Directional:
            s.wi = -e.n;
            s.dist = kInfinity;
            s.p_light = p - e.n * (2.f * radius_);
            s.pdf = 1.f;
            s.Li = e.value;
            return true;
        case EmitterType::Rect:
        case EmitterType::Mesh:
        case EmitterType::Sphere: {
            if (e.type == EmitterType::Sphere && e.solid_angle) {
                const float dc2 = length_squared(e.p - p);
                // From inside (two-sided emission) only area sampling applies.
                if (dc2 > e.radius * e.radius * 1.0001f) {
                    // Uniform in the cone the sphere subtends. The point is placed on the
                    // sphere by its angle at the centre (as pbrt-v4 does), not by
                    // intersecting the sampled ray: at the silhouette that intersection's
                    // rounding leaves it well off the sphere.
                    const float dc = std::sqrt(dc2);
                    const Vec3 wc = (e.p - p) / dc;
                    const float sin2_max = e.radius * e.radius / dc2;
                    const float one_minus_cos = cone_one_minus_cos(sin2_max);
                    const float v = u.x * one_minus_cos;
                    const float cos_t = 1.f - v, sin2_t = v * (2.f - v);
                    const float cos_a = sin2_t / std::sqrt(sin2_max) +
                                        cos_t * std::sqrt(std::max(0.f, 1.f - sin2_t / sin2_max));
                    const float sin_a = std::sqrt(std::max(0.f, 1.f - cos_a * cos_a));
                    const float phi = 2.f * kPi * u.y;
                    const warp::Frame fr(wc);
                    const Vec3 n =
                        fr.to_world({sin_a * std::cos(phi), sin_a * std::sin(phi), -cos_a});
                    s.p_light = e.p + n * e.radius;
                    const Vec3 to = s.p_light - p;
                    const float ds = length(to);
                    s.wi = to / ds;
                    s.dist = ds;
                    s.n_light = n;
                    s.pdf = 1.f / (2.f * kPi * one_minus_cos);
                    s.Li = e.texture >= 0
                               ? textured_radiance(e, TexPoint{sphere_uv(n), s.p_light, n})
                               : e.value;
                    return s.pdf > 0.f && ds > 0.f;
                }
            }
            Vec3 q, nq;
            RGB le;
            const float area = sample_area_point(e, u, uc, q, nq, le, tri);
            const Vec3 to = q - p;
            const float d2 = length_squared(to);
            if (d2 == 0.f) return false;
            s.dist = std::sqrt(d2);
            s.wi = to / s.dist;
            float cos_l = -dot(nq, s.wi);
            if (e.two_sided) cos_l = std::fabs(cos_l);
            if (cos_l <= 0.f) return false;  // one-sided: its back faces p
            s.p_light = q;
            s.n_light = dot(nq, s.wi) < 0.f ? nq : -nq;
            s.pdf = d2 / (cos_l * area);
            s.Li = le;
            return true;
        }
    }
    return false;
}

float LightSet::environment_pdf(const Vec3& wi) const {
    if (environment_ < 0) return 0.f;
    return pmf_[std::size_t(environment_)] * scene_->environment->pdf_emission(wi);
}

float LightSet::pdf_li(uint32_t i, const Vec3& p, const Vec3& q, const Vec3& nq,
                       uint32_t tri) const {
    const Emitter& e = emitters_[i];
    if (e.is_delta()) return 0.f;
    if (e.type == EmitterType::Environment) return scene_->environment->pdf(p, normalize(q - p));
    if (e.type == EmitterType::Sphere && e.solid_angle) {
        const float dc2 = length_squared(e.p - p);
        if (dc2 > e.radius * e.radius * 1.0001f) {
            return 1.f / (2.f * kPi * cone_one_minus_cos(e.radius * e.radius / dc2));
        }
    }
    const Vec3 to = q - p;
    const float d2 = length_squared(to);
    const float cos_l = std::fabs(dot(nq, to)) / std::sqrt(d2);
    if (cos_l == 0.f) return 0.f;
    return d2 / (cos_l * triangle_area(e, tri));
}

}  // namespace foton
