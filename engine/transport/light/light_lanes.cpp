// The light tracer's vertices on the kernel's materials (Lambertian, Oren–Nayar, Phong and
// microfacet lobes) through kern::shade_importance, 64 lanes a call: the hit, throughput,
// material, the eye and the bounce's four numbers in; the connections (projected onto the
// film and weighed by the camera's importance here) and continuations out.
#include <algorithm>

#include "engine/core/rng.h"
#include "engine/core/rng_streams.h"
#include "kernels/counter_hash.h"
#include "kernels/importance_shade.h"
#include "light_tracer.h"

namespace foton {

void LightTracer::shade_lanes(uint64_t first, uint32_t depth, LightTracerWorkspace& ws) const {
    const Scene& scene = ctx_.scene;
    const Camera& cam = scene.camera;
    const RenderSettings& rs = ctx_.settings;
    const uint32_t vertex = depth + 1;
    const bool continues = vertex < rs.max_depth, roulette = vertex >= rs.rr_depth;
    // The bounce's numbers as LightTracer::rand draws them: (lobe, roulette) and the
    // direction's two, by the kernel's columns kDvUChoice, kDvURoulette and kDvU0, kDvU1.
    const uint64_t prefix = kern::stream_prefix(ctx_.seed, kLightPathStream);
    const uint32_t dim = kLightDimFirstBounce + depth * kLightDimsPerBounce;
    const uint64_t direction_dims[2] = {dim + 1, dim + 2}, choice_dims[2] = {dim, dim + 3};
    static_assert(kern::kDvU1 == kern::kDvU0 + 1 && kern::kDvURoulette == kern::kDvUChoice + 1);
    KernelLanes& L = ws.lanes;
    const std::vector<uint32_t>& entries = ws.kernel_entries;
    for (std::size_t start = 0; start < entries.size(); start += KernelLanes::kLanes) {
        L.size = std::min(KernelLanes::kLanes, entries.size() - start);
        for (std::size_t k = 0; k < L.size; ++k) {
            const std::size_t i = entries[start + k];
            const uint32_t slot = ws.rays.id[i];
            L.entry[k] = uint32_t(i);
            L.slots[k] = slot;
            L.keys[k] = first + slot;
            if (!put_hit(L, k, scene, ws.rays, ws.hits, i))
                put_surface(L, k, surface_at(scene, ws.rays, ws.hits, i));
            L.put3(kern::kDvWox, k, -ws.rays.direction(i));
            L.put3(kern::kDvBetaR, k, ws.beta[slot]);
            L.put3(kern::kDvLpx, k, cam.eye);
            put_diffuse_material(L, k, kernels_, scene.objects[ws.hits.geom[i]].material);
        }
        // uniform_table reads keys up to the next multiple of 8: the lanes past the last keep
        // an earlier chunk's (or zero) and are never read back.
        kern::uniform_table(prefix, L.keys.data(), L.size, direction_dims, 2, L.col(kern::kDvU0),
                            KernelLanes::kLanes);
        kern::uniform_table(prefix, L.keys.data(), L.size, choice_dims, 2, L.col(kern::kDvUChoice),
                            KernelLanes::kLanes);
        kern::shade_importance(L.table(), L.size, roulette);

        const float* connect = L.col(kern::kDvShadowValid);
        const float* next = L.col(kern::kDvNextValid);
        for (std::size_t k = 0; k < L.size; ++k) {
            const uint32_t slot = L.slots[k];
            if (connect[k] != 0.f) {
                const Vec3 p = L.get3(kern::kDvPx, k), wc = L.get3(kern::kDvSdx, k);
                const Vec3 v = L.get3(kern::kDvSvR, k);
                FilmPoint at;
                RGB splat;
                if (to_film(p, wc, length(cam.eye - p), RGB{v.x, v.y, v.z}, at, splat))
                    push_connection(L.get3(kern::kDvSox, k), wc, L.col(kern::kDvStmax)[k], splat,
                                    at, slot, ws);
            }
            if (continues && next[k] != 0.f) {
                const Vec3 b = L.get3(kern::kDvNbetaR, k);
                ws.beta[slot] = RGB{b.x, b.y, b.z};
                ws.next.push(L.get3(kern::kDvNox, k), L.get3(kern::kDvNdx, k), 0.f, kInfinity,
                             slot);
            }
        }
    }
}

}  // namespace foton
