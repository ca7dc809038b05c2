#include "subsurface_exit.h"

#include <cmath>

#include "engine/core/rng.h"
#include "engine/scene/subsurface/tabulated_bssrdf.h"

namespace foton {

namespace {

// Hits a probe may pass before it gives up (a probe through a finely folded surface).
constexpr int kMaxProbeHits = 64;

}  // namespace

bool find_subsurface_exit(const Scene& scene, const Intersector& accel, uint32_t geom,
                          const Material& m, const SurfacePoint& entry, const float u[4],
                          TraceCounters& counters, SubsurfaceExitPoint& out) {
    const uint32_t material = scene.objects[geom].material;
    const Subsurface& sub = scene.subsurfaces[std::size_t(m.subsurface)];
    RGB sigma_a, sigma_s;
    sub.coefficients(m, sigma_a, sigma_s);
    const TabulatedBssrdf bssrdf(*sub.table, entry.p, entry.ns, sigma_a, sigma_s);
    BssrdfProbe probe;
    if (!bssrdf.sample_probe(u[0], {u[1], u[2]}, probe)) return false;
    const Vec3 span = probe.p1 - probe.p0;
    const float len = length(span);
    if (!(len > 0.f)) return false;
    const Vec3 dir = span / len;
    // Every hit on the material along the probe; the k-th replaces the pick with chance 1/k
    // (its number a hash of u[3], so each pick has its own).
    const uint64_t key = rng::hash(uint64_t(u[3] * 4294967296.0), 0x55b0, 0, 0);
    Vec3 o = probe.p0, pick_origin;
    float t_left = len;
    Hit1 pick;
    uint32_t hits = 0;
    for (int k = 0; k < kMaxProbeHits && t_left > 0.f; ++k) {
        const kern::Ray1 ray{o.x, o.y, o.z, dir.x, dir.y, dir.z, 0.f, t_left};
        Hit1 h;
        if (!accel.intersect1(ray, h, counters)) break;
        if (scene.objects[h.geom].material == material) {
            ++hits;
            if (rng::uniform_from(key, 0, hits) * float(hits) < 1.f) {
                pick = h;
                pick_origin = o;
            }
        }
        // On from just past the hit.
        const float step = h.t + offset_epsilon(o + dir * h.t, h.t);
        o = o + dir * step;
        t_left -= step;
    }
    if (hits == 0) return false;
    SurfacePoint sp =
        surface_at(scene, pick.geom, pick.prim, pick.t, pick.u, pick.v, pick_origin, dir);
    // Face the normals out of the material: the side the geometry's own normal points to.
    if (!sp.front_face) {
        sp.ng = -sp.ng;
        sp.ns = -sp.ns;
        sp.front_face = true;
    }
    const float pdf = bssrdf.pdf_sp(sp.p, sp.ng) / float(hits);
    if (!(pdf > 0.f)) return false;
    out.sp = sp;
    out.geom = pick.geom;
    out.weight = bssrdf.sp(sp.p) * (1.f / pdf);
    return true;
}

}  // namespace foton
