#include "light_set.h"

#include <cmath>

#include "engine/core/warp.h"

// Emission: the rays light tracing and photon emission start with, and their densities
// (what bidirectional MIS weighs a light vertex by). Next event estimation is in
// light_set.cpp.

namespace foton {

bool LightSet::sample_ray(float u_select, Point2 u_pos, Point2 u_dir, float uc,
                          EmittedRay& r) const {
    r.light = select(u_select, r.pmf);
    EmissionSample& es = r.emission;
    if (!sample_le(r.light, u_pos, u_dir, uc, es)) return false;
    const bool area = !emitters_[r.light].is_delta();
    const float cos_e = area ? std::fabs(dot(es.n, es.dir)) : 1.f;
    r.beta = es.Le * (cos_e / (r.pmf * es.pdf_pos * es.pdf_dir));
    r.origin = area ? es.p + es.n * offset_epsilon(es.p, 0.f) : es.p;
    return true;
}

bool LightSet::sample_le(uint32_t i, Point2 u_pos, Point2 u_dir, float uc,
                         EmissionSample& s) const {
    const Emitter& e = emitters_[i];
    switch (e.type) {
        case EmitterType::Point:
            s.p = e.p;
            s.n = {};
            s.pdf_pos = 1.f;
            s.Le = e.value;
            // Towards geometry only, with projection maps (direction_projection.h).
            if (const DirectionProjection* maps = direction_projection(i)) {
                s.dir = maps->sample(u_dir, s.pdf_dir);
                return s.pdf_dir > 0.f;
            }
            s.dir = warp::uniform_sphere(u_dir);
            s.pdf_dir = warp::kUniformSpherePdf;
            return true;
        case EmitterType::Spot: {
            s.p = e.p;
            s.n = {};
            s.pdf_pos = 1.f;
            if (const DirectionProjection* maps = direction_projection(i)) {
                s.dir = maps->sample(u_dir, s.pdf_dir);
                s.Le = e.value * e.spot_falloff(dot(s.dir, e.n));
                return s.pdf_dir > 0.f && !s.Le.is_black();
            }
            const warp::Frame fr(e.n);
            const Vec3 local = warp::uniform_cone(u_dir, e.cos_outer);
            s.dir = fr.to_world(local);
            s.pdf_dir = warp::uniform_cone_pdf(e.cos_outer);
            s.Le = e.value * e.spot_falloff(local.z);
            return !s.Le.is_black();
        }
        case EmitterType::Environment: {
            // A direction towards the sky by its density; the ray comes from there, through
            // a disc covering the scene's bounding sphere, upstream of it.
            float pdf;
            const Vec3 wi = scene_->environment->sample_emission(u_dir, pdf);
            if (!(pdf > 0.f)) return false;
            // Or, with projection maps, over the geometry's outline seen from wi's bin.
            if (const EnvironmentProjection* maps = environment_projection()) {
                maps->sample(wi, u_pos, s.p, s.pdf_pos);
            } else {
                const warp::Frame fr(-wi);
                const Point2 d = warp::concentric_disc(u_pos);
                s.p = center_ + fr.to_world({d.x * radius_, d.y * radius_, -radius_ * 1.01f});
                s.pdf_pos = 1.f / (kPi * radius_ * radius_);
            }
            s.n = -wi;
            s.dir = -wi;
            s.pdf_dir = pdf;
            s.Le = scene_->environment->Le_emitted(s.p, wi);
            return !s.Le.is_black();
        }
        case EmitterType::Directional: {
            // A disc covering the scene's bounding sphere, upstream of it, or the cells of
            // its projection map that lie over geometry.
            const warp::Frame fr(e.n);
            const ProjectionMap& map = projection_[i];
            if (!map.empty()) {
                const Point2 q = map.sample(u_pos);
                s.p = center_ + fr.s * q.x + fr.t * q.y - fr.n * (radius_ * 1.01f);
                s.pdf_pos = 1.f / map.area();
            } else {
                const Point2 d = warp::concentric_disc(u_pos);
                s.p = center_ + fr.to_world({d.x * radius_, d.y * radius_, -radius_ * 1.01f});
                s.pdf_pos = 1.f / (kPi * radius_ * radius_);
            }
            s.n = e.n;
            s.dir = e.n;
            s.pdf_dir = 1.f;
            s.Le = e.value;
            return true;
        }
        case EmitterType::Rect:
        case EmitterType::Sphere:
        case EmitterType::Mesh: {
            Vec3 q, nq;
            RGB le;
            sample_area_point(e, u_pos, uc, q, nq, le);
            float side_pdf = 1.f;
            if (e.two_sided) {
                // Either side with probability 1/2: u_dir.x picks it and is stretched back.
                side_pdf = 0.5f;
                if (u_dir.x < 0.5f) {
                    u_dir.x *= 2.f;
                } else {
                    u_dir.x = std::min(2.f * u_dir.x - 1.f, 0x1.fffffep-1f);
                    nq = -nq;
                }
            }
            const warp::Frame fr(nq);
            const Vec3 local = warp::cosine_hemisphere(u_dir);
            s.p = q;
            s.n = nq;
            s.dir = fr.to_world(local);
            s.pdf_pos = 1.f / e.area;
            s.pdf_dir = side_pdf * warp::cosine_hemisphere_pdf(local.z);
            s.Le = le;
            return s.pdf_dir > 0.f;
        }
    }
    return false;
}

void LightSet::pdf_le(uint32_t i, const Vec3& nq, const Vec3& dir, float& pdf_pos,
                      float& pdf_dir) const {
    const Emitter& e = emitters_[i];
    pdf_pos = 1.f;
    pdf_dir = 0.f;
    switch (e.type) {
        case EmitterType::Point:
            if (const DirectionProjection* maps = direction_projection(i))
                pdf_dir = maps->pdf(dir);
            else
                pdf_dir = warp::kUniformSpherePdf;
            return;
        case EmitterType::Spot:
            if (const DirectionProjection* maps = direction_projection(i))
                pdf_dir = maps->pdf(dir);
            else
                pdf_dir = dot(dir, e.n) >= e.cos_outer ? warp::uniform_cone_pdf(e.cos_outer) : 0.f;
            return;
        case EmitterType::Environment: {
            // Light arrives only where geometry is: through a kept cell of -dir's bin.
            const EnvironmentProjection* maps = environment_projection();
            pdf_pos = maps ? maps->pdf_pos(-dir) : 1.f / (kPi * radius_ * radius_);
            pdf_dir = scene_->environment->pdf_emission(-dir);
            return;
        }
        case EmitterType::Directional:
            // Light arrives only where geometry is: in a kept cell of the map, if it has one.
            pdf_pos = projection_[i].empty() ? 1.f / (kPi * radius_ * radius_)
                                             : 1.f / projection_[i].area();
            pdf_dir = 1.f;
            return;
        case EmitterType::Rect:
        case EmitterType::Sphere:
        case EmitterType::Mesh: {
            pdf_pos = 1.f / e.area;
            const float c = dot(nq, dir);
            if (e.two_sided)
                pdf_dir = 0.5f * std::fabs(c) * kInvPi;
            else
                pdf_dir = c > 0.f ? c * kInvPi : 0.f;
            return;
        }
    }
}

}  // namespace foton
