// The path tracer's mirror and dielectric vertices through kern::shade_specular: a chunk of
// lanes is filled from the batch (the hit, throughput, the material, the lobe's and
// roulette's numbers), shaded at SIMD width, and read back into continuation rays and the
// paths' state, as shade_vertex's delta-lobe branch would leave them.
#include <algorithm>

#include "engine/transport/common/surface.h"
#include "kernels/specular_shade.h"
#include "path.h"

namespace foton {

void PathIntegrator::fill_specular_lane(uint32_t depth, std::size_t lane, PathWorkspace& ws) const {
    DiffuseLanes& L = ws.diffuse;
    const std::size_t i = L.entry[lane];
    const uint32_t slot = ws.rays.id[i];
    ws.path_length[slot] += ws.hits.t[i];
    auto put3 = [&](uint32_t c, float x, float y, float z) {
        L.col(c)[lane] = x;
        L.col(c + 1)[lane] = y;
        L.col(c + 2)[lane] = z;
    };
    auto put_rgb = [&](uint32_t c, const RGB& v) { put3(c, v.r, v.g, v.b); };
    SurfacePoint sp;
    put_surface(lane, i, ws, false, sp);
    put3(kern::kDvWox, -ws.rays.dx[i], -ws.rays.dy[i], -ws.rays.dz[i]);
    put_rgb(kern::kDvBetaR, ws.beta[slot]);
    L.col(kern::kDvEtaScale)[lane] = ws.eta_scale[slot];
    const SpecularMaterial& m = diffuse_.specular[ctx_.scene.objects[ws.hits.geom[i]].material];
    L.col(kern::kDvSpecKind)[lane] = m.kind;
    put_rgb(kern::kDvSpecR, m.color);
    put_rgb(kern::kDvTransR, m.transmit);
    L.col(kern::kDvFresnel)[lane] = m.fresnel;
    L.col(kern::kDvIor)[lane] = m.ior;
    put_rgb(kern::kDvEtaR, m.eta);
    put_rgb(kern::kDvKR, m.k);
    L.col(kern::kDvLobeWeight)[lane] = m.weight;
    const float* rand = L.rand.data();
    const std::size_t stride = DiffuseLanes::kLanes;
    L.col(kern::kDvUChoice)[lane] = L.drawn ? rand[DiffuseLanes::kRandLobe * stride + lane]
                                            : this->rand(ws, slot, depth, kPathDimBsdf);
    L.col(kern::kDvURoulette)[lane] = depth + 1 < ctx_.settings.rr_depth ? 0.f
                                      : L.drawn ? rand[DiffuseLanes::kRandRoulette * stride + lane]
                                                : this->rand(ws, slot, depth, kPathDimRoulette);
}

void PathIntegrator::read_specular_lanes(PathWorkspace& ws) const {
    DiffuseLanes& L = ws.diffuse;
    const float* valid = L.col(kern::kDvNextValid);
    std::size_t nexts = 0;
    for (std::size_t k = 0; k < L.size; ++k) nexts += valid[k] != 0.f;
    RayBatch& nb = ws.next;
    std::size_t n = nb.size();
    nb.resize(n + nexts);
    for (std::size_t k = 0; k < L.size; ++k) {
        if (valid[k] == 0.f) continue;
        const uint32_t slot = ws.rays.id[L.entry[k]];
        ws.beta[slot] =
            RGB{L.col(kern::kDvNbetaR)[k], L.col(kern::kDvNbetaG)[k], L.col(kern::kDvNbetaB)[k]};
        ws.eta_scale[slot] = L.col(kern::kDvNetaScale)[k];
        ws.pdf_prev[slot] = L.col(kern::kDvNpdf)[k];
        ws.specular_prev[slot] = 1;
        // A specular bounce after the first non-specular vertex makes what it finds a caustic
        // there (shade_vertex).
        if (ws.nondelta[slot] == 1) ws.nondelta[slot] = 2;
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

void PathIntegrator::shade_specular(uint32_t depth, PathWorkspace& ws) const {
    DiffuseLanes& L = ws.diffuse;
    const bool roulette = depth + 1 >= ctx_.settings.rr_depth;
    const std::size_t width = kern::diffuse_shade_width();
    const std::vector<uint32_t>& entries = ws.specular_entries;
    for (std::size_t start = 0; start < entries.size(); start += DiffuseLanes::kLanes) {
        L.size = std::min(DiffuseLanes::kLanes, entries.size() - start);
        for (std::size_t k = 0; k < L.size; ++k) L.entry[k] = entries[start + k];
        draw_lane_numbers(depth, ws);
        for (std::size_t k = 0; k < L.size; ++k) fill_specular_lane(depth, k, ws);
        // The lanes past the last up to the SIMD width: zeros, which make no rays.
        const std::size_t padded = (L.size + width - 1) / width * width;
        for (uint32_t c = 0; c < kern::kDiffuseColumns; ++c)
            std::fill(L.col(c) + L.size, L.col(c) + padded, 0.f);
        kern::shade_specular(L.table(), L.size, roulette);
        read_specular_lanes(ws);
    }
}

}  // namespace foton
