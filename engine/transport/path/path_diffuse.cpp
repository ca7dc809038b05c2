// The path tracer's Lambertian vertices through kern::shade_diffuse: a chunk of lanes is
// filled from the batch (the hit, throughput, the light, the random numbers: path_lanes.cpp),
// shaded at SIMD width, and read back into shadow rays, continuation rays and the paths'
// state. What stays scalar here: choosing the light, sampling lights other than rectangles
// (and then the surface point they need), instances' surfaces.
#include <algorithm>
#include <cmath>

#include "engine/transport/common/surface.h"
#include "path.h"

namespace foton {

void PathIntegrator::fill_diffuse_lane(uint32_t depth, std::size_t lane, PathWorkspace& ws) const {
    DiffuseLanes& L = ws.diffuse;
    const std::size_t i = L.entry[lane];
    const uint32_t slot = ws.rays.id[i];
    // Number `row` of the drawn table, or the sampler's number k.
    auto draw = [&](uint32_t row, uint32_t k) {
        return L.drawn ? L.rand[row * DiffuseLanes::kLanes + lane] : rand(ws, slot, depth, k);
    };
    auto draw2 = [&](uint32_t row, uint32_t k) {
        return L.drawn ? Point2{L.rand[row * DiffuseLanes::kLanes + lane],
                                L.rand[(row + 1) * DiffuseLanes::kLanes + lane]}
                       : rand2(ws, slot, depth, k);
    };
    ws.path_length[slot] += ws.hits.t[i];
    auto put3 = [&](uint32_t c, float x, float y, float z) {
        L.col(c)[lane] = x;
        L.col(c + 1)[lane] = y;
        L.col(c + 2)[lane] = z;
    };
    put3(kern::kDvWox, -ws.rays.dx[i], -ws.rays.dy[i], -ws.rays.dz[i]);
    const uint32_t material = ctx_.scene.objects[ws.hits.geom[i]].material;
    const RGB& rho = diffuse_.rho[material];
    put3(kern::kDvRhoR, rho.r, rho.g, rho.b);
    L.col(kern::kDvOnA)[lane] = diffuse_.on_a[material];
    L.col(kern::kDvOnB)[lane] = diffuse_.on_b[material];
    const RGB& beta = ws.beta[slot];
    put3(kern::kDvBetaR, beta.r, beta.g, beta.b);
    L.col(kern::kDvEtaScale)[lane] = ws.eta_scale[slot];
    // The light, as shade_vertex's next event estimation chooses it. The kernel samples a
    // rectangle and makes the surface itself; any other light is sampled here, from the
    // surface point surface_at makes here.
    const bool nee = rules_.nee && !ctx_.lights.empty();
    float pick = 0.f;
    const uint32_t li =
        nee ? ctx_.lights.select(draw(DiffuseLanes::kRandLightSelect, kPathDimLightSelect), pick)
            : 0;
    const Emitter* e = nee ? &ctx_.lights.emitter(li) : nullptr;
    const bool rect = e && e->type == EmitterType::Rect;
    SurfacePoint sp;
    put_surface(lane, i, ws, e && !rect, sp);
    float pdf = 0.f, full = 1.f;
    const bool no_mis = rules_.mis.heuristic == MisHeuristic::None;
    LightSample ls;
    if (rect) {
        const Point2 ul = draw2(DiffuseLanes::kRandLight, kPathDimLight);
        pdf = pick;
        full = no_mis ? 1.f : 0.f;
        ls.p_light = e->p;
        ls.n_light = e->n;
        ls.Li = e->value;
        put3(kern::kDvLe1x, e->e1.x, e->e1.y, e->e1.z);
        put3(kern::kDvLe2x, e->e2.x, e->e2.y, e->e2.z);
        L.col(kern::kDvLarea)[lane] = e->area;
        L.col(kern::kDvLu0)[lane] = ul.x;
        L.col(kern::kDvLu1)[lane] = ul.y;
    } else if (e &&
               ctx_.lights.sample_li(li, sp.p, draw2(DiffuseLanes::kRandLight, kPathDimLight),
                                     draw(DiffuseLanes::kRandLightUc, kPathDimLight + 2), ls)) {
        pdf = pick * ls.pdf;
        full = no_mis || e->is_delta() ? 1.f : 0.f;
    }
    L.col(kern::kDvLrect)[lane] = rect ? 1.f : 0.f;
    L.col(kern::kDvLightPdf)[lane] = pdf;
    L.col(kern::kDvLightFull)[lane] = full;
    put3(kern::kDvLwx, ls.wi.x, ls.wi.y, ls.wi.z);
    L.col(kern::kDvLdist)[lane] = ls.dist;
    put3(kern::kDvLpx, ls.p_light.x, ls.p_light.y, ls.p_light.z);
    put3(kern::kDvLnx, ls.n_light.x, ls.n_light.y, ls.n_light.z);
    put3(kern::kDvLiR, ls.Li.r, ls.Li.g, ls.Li.b);
    const Point2 u = draw2(DiffuseLanes::kRandBsdf, kPathDimBsdf + 1);
    L.col(kern::kDvU0)[lane] = u.x;
    L.col(kern::kDvU1)[lane] = u.y;
    L.col(kern::kDvURoulette)[lane] = depth + 1 >= ctx_.settings.rr_depth
                                          ? draw(DiffuseLanes::kRandRoulette, kPathDimRoulette)
                                          : 0.f;
}

void PathIntegrator::read_diffuse_lanes(PathWorkspace& ws) const {
    DiffuseLanes& L = ws.diffuse;
    const float* shadow_valid = L.col(kern::kDvShadowValid);
    const float* next_valid = L.col(kern::kDvNextValid);
    std::size_t shadows = 0, nexts = 0;
    for (std::size_t k = 0; k < L.size; ++k) {
        shadows += shadow_valid[k] != 0.f;
        nexts += next_valid[k] != 0.f;
    }
    // Both batches grown once and written column by column (not a push per ray).
    RayBatch& sb = ws.shadow;
    std::size_t s = sb.size();
    sb.resize(s + shadows);
    ws.shadow_value.resize(s + shadows);
    RayBatch& nb = ws.next;
    std::size_t n = nb.size();
    nb.resize(n + nexts);
    for (std::size_t k = 0; k < L.size; ++k) {
        const uint32_t slot = ws.rays.id[L.entry[k]];
        if (shadow_valid[k] != 0.f) {
            sb.ox[s] = L.col(kern::kDvSox)[k];
            sb.oy[s] = L.col(kern::kDvSoy)[k];
            sb.oz[s] = L.col(kern::kDvSoz)[k];
            sb.dx[s] = L.col(kern::kDvSdx)[k];
            sb.dy[s] = L.col(kern::kDvSdy)[k];
            sb.dz[s] = L.col(kern::kDvSdz)[k];
            sb.tmin[s] = 0.f;
            sb.tmax[s] = L.col(kern::kDvStmax)[k];
            sb.id[s] = slot;
            ws.shadow_value[s] =
                RGB{L.col(kern::kDvSvR)[k], L.col(kern::kDvSvG)[k], L.col(kern::kDvSvB)[k]};
            ++s;
        }
        if (next_valid[k] == 0.f) continue;
        ws.beta[slot] =
            RGB{L.col(kern::kDvNbetaR)[k], L.col(kern::kDvNbetaG)[k], L.col(kern::kDvNbetaB)[k]};
        ws.pdf_prev[slot] = L.col(kern::kDvNpdf)[k];
        ws.specular_prev[slot] = 0;
        ws.nondelta[slot] = uint8_t(std::min(2, ws.nondelta[slot] + 1));
        ws.chain_specular[slot] = 0;
        ws.p_prev[slot] = Vec3{L.col(kern::kDvPx)[k], L.col(kern::kDvPy)[k], L.col(kern::kDvPz)[k]};
        nb.ox[n] = L.col(kern::kDvNox)[k];
        nb.oy[n] = L.col(kern::kDvNoy)[k];
        nb.oz[n] = L.col(kern::kDvNoz)[k];
        nb.dx[n] = L.col(kern::kDvNdx)[k];
        nb.dy[n] = L.col(kern::kDvNdy)[k];
        nb.dz[n] = L.col(kern::kDvNdz)[k];
        nb.tmin[n] = 0.f;
        nb.tmax[n] = kInfinity;
        nb.id[n] = slot;
        ++n;
    }
}

void PathIntegrator::shade_diffuse(uint32_t depth, PathWorkspace& ws) const {
    DiffuseLanes& L = ws.diffuse;
    kern::DiffuseRules rules = diffuse_.rules;
    rules.roulette = depth + 1 >= ctx_.settings.rr_depth;
    const std::size_t width = kern::diffuse_shade_width();
    const std::vector<uint32_t>& entries = ws.diffuse_entries;
    for (std::size_t start = 0; start < entries.size(); start += DiffuseLanes::kLanes) {
        L.size = std::min(DiffuseLanes::kLanes, entries.size() - start);
        for (std::size_t k = 0; k < L.size; ++k) L.entry[k] = entries[start + k];
        draw_lane_numbers(depth, ws);
        for (std::size_t k = 0; k < L.size; ++k) fill_diffuse_lane(depth, k, ws);
        // The lanes past the last up to the SIMD width: zeros, which make no rays.
        const std::size_t padded = (L.size + width - 1) / width * width;
        for (uint32_t c = 0; c < kern::kDiffuseColumns; ++c)
            std::fill(L.col(c) + L.size, L.col(c) + padded, 0.f);
        kern::shade_diffuse(L.table(), L.size, rules);
        read_diffuse_lanes(ws);
    }
}

}  // namespace foton
