// The lanes of the path tracer's mirror and dielectric vertices for kern::shade_specular: the
// hit, throughput, the material, the lobe's and roulette's numbers (path_lanes.cpp runs the
// chunks and reads them back).
#include "engine/transport/common/surface.h"
#include "path.h"

namespace foton {

void PathIntegrator::fill_specular_lane(uint32_t depth, std::size_t lane, PathWorkspace& ws) const {
    KernelLanes& L = ws.lanes;
    const std::size_t i = L.entry[lane];
    put_path(lane, ws);
    SurfacePoint sp;
    put_surface(lane, i, ws, false, sp);
    const SpecularMaterial& m = kernels_.specular[ctx_.scene.objects[ws.hits.geom[i]].material];
    L.col(kern::kDvSpecKind)[lane] = m.kind;
    L.put3(kern::kDvSpecR, lane, m.color);
    L.put3(kern::kDvTransR, lane, m.transmit);
    L.col(kern::kDvFresnel)[lane] = m.fresnel;
    L.col(kern::kDvIor)[lane] = m.ior;
    L.put3(kern::kDvEtaR, lane, m.eta);
    L.put3(kern::kDvKR, lane, m.k);
    L.col(kern::kDvLobeWeight)[lane] = m.weight;
    // The numbers the kernel reads are in the table already when they were drawn as one.
    if (!L.drawn) {
        L.col(kern::kDvUChoice)[lane] =
            lane_number(ws, lane, KernelLanes::kRandLobe, depth, kPathDimBsdf);
        if (depth + 1 >= ctx_.settings.rr_depth)
            L.col(kern::kDvURoulette)[lane] =
                lane_number(ws, lane, KernelLanes::kRandRoulette, depth, kPathDimRoulette);
    }
}

}  // namespace foton
