// Final gathering's photon estimates for a whole batch of gather hits: precomputed irradiance
// where it serves, else full estimates by a batched kNN search or by reverse photon mapping.
#include "photon_integrator.h"

#include "engine/core/warp.h"

namespace foton {

void PhotonIntegrator::photon_radiance_batch(FinalGatherBatch& b) const {
    const std::size_t n = b.hits.size();
    b.L.assign(n, RGB{0.f});
    for (const PhotonMap* map : {&maps_.global, &maps_.direct}) {
        if (map->empty()) continue;
        // Lambertian hits read Christensen's precomputed irradiance when there is one nearby
        // with a similar normal (all such lookups in one batch); anything else takes a full
        // estimate. As in photon_radiance.
        b.lambert.clear();
        b.rho.clear();
        b.queries.clear();
        std::vector<uint8_t>& served = b.found;
        if (map->has_precomputed()) {
            for (uint32_t i = 0; i < n; ++i) {
                RGB rho;
                if (!b.hits[i].m->bsdf.lambert_albedo(rho)) continue;
                b.lambert.push_back(i);
                b.rho.push_back(rho);
                b.queries.push(b.hits[i].sp.p, b.hits[i].sp.ng, maps_.global_params.max_radius);
            }
            map->lookup_irradiance_batch(b.queries, b.e, served);
        }
        std::size_t next = 0;
        b.full.clear();
        b.fx.clear();
        b.fy.clear();
        b.fz.clear();
        for (uint32_t i = 0; i < n; ++i) {
            const FinalGatherBatch::Hit& h = b.hits[i];
            if (next < b.lambert.size() && b.lambert[next] == i) {
                const std::size_t j = next++;
                if (served[j]) {
                    b.L[i] += b.rho[j] * b.e[j] * kInvPi;
                    continue;
                }
            }
            b.full.push_back(i);
            b.fx.push_back(h.sp.p.x);
            b.fy.push_back(h.sp.p.y);
            b.fz.push_back(h.sp.p.z);
        }
        // The full estimates' kNN queries as one batch too.
        if (b.full.empty()) continue;
        const EstimateParams& gp = maps_.global_params;
        const auto estimate = [&](std::size_t q, uint32_t count, uint32_t* idx, float* d2) {
            const FinalGatherBatch::Hit& h = b.hits[b.full[q]];
            const warp::Frame frame = h.sp.frame();
            const BsdfContext ctx{h.sp.front_face, Transport::Radiance};
            b.L[b.full[q]] += map->radiance_from(h.sp.p, frame.s, frame.t, frame.n, h.m->bsdf,
                                                 frame.to_local(-h.d), ctx, gp, count, idx, d2);
        };
        if (ctx_.settings.photon.reverse_lookup) {  // photons find the hits (reverse_photons.h)
            reverse_gather(*map, b.fx.data(), b.fy.data(), b.fz.data(), b.full.size(), gp,
                           b.reverse, estimate);
            continue;
        }
        map->knn_batch(b.fx.data(), b.fy.data(), b.fz.data(), b.full.size(), gp, b.knn);
        for (std::size_t q = 0; q < b.full.size(); ++q) {
            const std::size_t row = q * b.knn.k;
            estimate(q, b.knn.count[q], b.knn.index.data() + row, b.knn.dist2.data() + row);
        }
    }
}

}  // namespace foton
