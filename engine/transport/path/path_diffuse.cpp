// The lanes of the path tracer's Lambertian and Oren–Nayar vertices for kern::shade_diffuse:
// the hit, throughput, material, the light and the random numbers (path_lanes.cpp runs the
// chunks and reads them back). What stays scalar here: choosing the light, placing a mesh
// light's triangle, sampling lights other than rectangles, triangles and one-sided spheres
// (and then the surface point they need), instances' surfaces.
#include <algorithm>
#include <cmath>

#include "engine/transport/common/surface.h"
#include "path.h"

namespace foton {

// The lights the kernel samples itself: rectangles, the triangles of emissive meshes, and
// one-sided spheres by their cone (from inside one it gives nothing, as sample_li); 0 for the
// others, sampled before the kernel.
float PathIntegrator::kernel_light_kind(const Emitter& e) {
    if (e.texture >= 0) return 0.f;  // its radiance varies: sample_li evaluates the texture
    switch (e.type) {
        case EmitterType::Rect:
            return kern::kLightParallelogram;
        case EmitterType::Mesh:
            return kern::kLightTriangle;
        case EmitterType::Sphere:
            return e.solid_angle && !e.two_sided ? kern::kLightSphere : 0.f;
        default:
            return 0.f;
    }
}

// Such a light's columns: its corner or centre, normal and radiance (in ls), its edges, a
// triangle's other corners or the radius, the area its point is uniform over, and the two
// numbers that place the point.
void PathIntegrator::put_kernel_light(uint32_t depth, std::size_t lane, const Emitter& e,
                                      const LightPick& pick, LightSample& ls,
                                      PathWorkspace& ws) const {
    KernelLanes& L = ws.lanes;
    if (!L.drawn) {
        const Point2 ul = lane_number2(ws, lane, KernelLanes::kRandLight, depth, kPathDimLight);
        L.col(kern::kDvLu0)[lane] = ul.x;
        L.col(kern::kDvLu1)[lane] = ul.y;
    }
    L.col(kern::kDvLtwoSided)[lane] = e.two_sided ? 1.f : 0.f;
    ls.Li = e.value;
    ls.p_light = e.p;
    if (e.type == EmitterType::Sphere) {
        L.col(kern::kDvLe1x)[lane] = e.radius;
    } else if (e.type == EmitterType::Rect) {
        ls.n_light = e.n;
        L.put3(kern::kDvLe1x, lane, e.e1);
        L.put3(kern::kDvLe2x, lane, e.e2);
        L.col(kern::kDvLarea)[lane] = e.area;
    } else {
        // The triangle the pick chose (light BVH), or one by area as sample_li picks it, with
        // the whole mesh's area in the density then.
        const uint32_t t =
            pick.tri != kWholeEmitter
                ? pick.tri
                : ctx_.lights.triangle_by_area(e, lane_number(ws, lane, KernelLanes::kRandLightUc,
                                                              depth, kPathDimLight + 2));
        Vec3 p0, p1, p2;
        ctx_.scene.world_corners(e.geom, t, p0, p1, p2);
        const Vec3 c = cross(p1 - p0, p2 - p0);
        ls.p_light = p0;
        ls.n_light = normalize(c);
        L.put3(kern::kDvLe1x, lane, p1);
        L.put3(kern::kDvLe2x, lane, p2);
        L.col(kern::kDvLarea)[lane] = pick.tri != kWholeEmitter ? 0.5f * length(c) : e.area;
    }
}

void PathIntegrator::fill_diffuse_lane(uint32_t depth, std::size_t lane, PathWorkspace& ws) const {
    KernelLanes& L = ws.lanes;
    const std::size_t i = L.entry[lane];
    put_path(lane, ws);
    auto draw = [&](uint32_t row, uint32_t k) { return lane_number(ws, lane, row, depth, k); };
    auto draw2 = [&](uint32_t row, uint32_t k) { return lane_number2(ws, lane, row, depth, k); };
    const uint32_t material = ctx_.scene.objects[ws.hits.geom[i]].material;
    put_diffuse_material(L, lane, kernels_, material);
    if (kernels_.glossy[material].kind != 0.f && !L.drawn)
        L.col(kern::kDvUChoice)[lane] = draw(KernelLanes::kRandLobe, kPathDimBsdf);
    // The light, as shade_vertex's next event estimation chooses it. The kernel samples
    // rectangles, triangles and one-sided spheres and makes the surface itself; any other
    // light is sampled here, from the surface point surface_at makes here. Under the light
    // BVH, whose pick needs that point, pick_lane_lights has made it and picked already.
    const bool nee = rules_.nee && !ctx_.lights.empty();
    SurfacePoint& sp = L.surface[lane];
    LightPick pick;
    bool picked = false;
    if (L.picked) {
        pick = L.picks.out[lane];
        picked = pick.pmf > 0.f;
    } else if (nee) {
        // Power and uniform selection do not look at the receiver.
        picked = ctx_.lights.pick(draw(KernelLanes::kRandLightSelect, kPathDimLightSelect), Vec3{},
                                  Vec3{}, pick);
    }
    const Emitter* e = picked ? &ctx_.lights.emitter(pick.light) : nullptr;
    const float kind = e ? kernel_light_kind(*e) : 0.f;
    if (!L.picked) put_surface(lane, i, ws, e && kind == 0.f, sp);
    float pdf = 0.f, full = 1.f;
    const bool no_mis = rules_.mis.heuristic == MisHeuristic::None;
    LightSample ls;
    if (kind != 0.f) {
        pdf = pick.pmf;
        full = no_mis ? 1.f : 0.f;
        put_kernel_light(depth, lane, *e, pick, ls, ws);
    } else if (e && ctx_.lights.sample_li(
                        pick.light, sp.p, draw2(KernelLanes::kRandLight, kPathDimLight),
                        draw(KernelLanes::kRandLightUc, kPathDimLight + 2), ls, pick.tri)) {
        pdf = pick.pmf * ls.pdf;
        full = no_mis || e->is_delta() ? 1.f : 0.f;
    }
    L.col(kern::kDvLkind)[lane] = kind;
    L.col(kern::kDvLightPdf)[lane] = pdf;
    L.col(kern::kDvLightFull)[lane] = full;
    if (kind == 0.f) {  // the kernel's own lights make these
        L.put3(kern::kDvLwx, lane, ls.wi);
        L.col(kern::kDvLdist)[lane] = ls.dist;
    }
    L.put3(kern::kDvLpx, lane, ls.p_light);
    L.put3(kern::kDvLnx, lane, ls.n_light);
    L.put3(kern::kDvLiR, lane, ls.Li);
    // The numbers the kernel reads are in the table already when they were drawn as one.
    if (!L.drawn) {
        const Point2 u = draw2(KernelLanes::kRandBsdf, kPathDimBsdf + 1);
        L.col(kern::kDvU0)[lane] = u.x;
        L.col(kern::kDvU1)[lane] = u.y;
        if (depth + 1 >= ctx_.settings.rr_depth)
            L.col(kern::kDvURoulette)[lane] = draw(KernelLanes::kRandRoulette, kPathDimRoulette);
    }
}

}  // namespace foton
