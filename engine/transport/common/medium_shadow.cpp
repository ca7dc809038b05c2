#include "medium_shadow.h"

#include <utility>

#include "engine/core/rng.h"
#include "engine/core/rng_streams.h"

namespace foton {

void MediumShadowRays::clear() {
    rays_.clear();
    state_.clear();
}

void MediumShadowRays::push(const Vec3& origin, const Vec3& dir, float tmax, int32_t medium,
                            uint32_t slot, const RGB& value, uint64_t key) {
    rays_.push(origin, dir, 0.f, tmax, uint32_t(state_.size()));
    const Vec3 end = std::isinf(tmax) ? Vec3{} : origin + dir * tmax;
    state_.push_back({slot, medium, 0, 0, key, value, end});
}

void MediumShadowRays::resolve(const Scene& scene, const Intersector& accel,
                               TransmittanceEstimator estimator, uint64_t seed,
                               std::vector<RGB>& radiance, RenderStats& stats, StageClock& clock,
                               const std::vector<Wavelengths>* wavelengths) {
    const uint64_t prefix = rng::stream_prefix(seed, kMediumShadowStream);
    uint64_t traced = 0;
    while (!rays_.empty()) {
        accel.intersect(rays_, hits_, stats.trace);
        traced += rays_.size();
        next_.clear();
        next_state_.clear();
        for (std::size_t i = 0; i < rays_.size(); ++i) {
            State& s = state_[rays_.id[i]];
            const bool hit = hits_.geom[i] != kNoHit;
            if (s.medium != kNoMedium) {
                const float d = hit ? hits_.t[i] : rays_.tmax[i];
                auto u = [&] { return rng::uniform_from(prefix, s.key, s.draws++); };
                const Medium& m = scene.media[std::size_t(s.medium)];
                if (wavelengths)
                    s.value *= transmittance(SpectralMedium(m, (*wavelengths)[s.slot]),
                                             rays_.origin(i), rays_.direction(i), d, estimator, u);
                else
                    s.value *=
                        transmittance(m, rays_.origin(i), rays_.direction(i), d, estimator, u);
                if (s.value.is_black()) continue;
            }
            if (!hit) {
                radiance[s.slot] += s.value;
                continue;
            }
            const uint32_t geom = hits_.geom[i];
            if (!scene.material_of(geom).is_interface || ++s.crossings > kMaxShadowCrossings)
                continue;  // blocked
            const Vec3 dir = rays_.direction(i);
            const SurfacePoint sp = surface_at(scene, rays_, hits_, i);
            s.medium = medium_after(scene, geom, sp, dir, s.medium);
            const Vec3 o = offset_origin(sp, dir);
            const float rest = std::isinf(rays_.tmax[i]) ? kInfinity : dot(s.end - o, dir);
            if (!(rest > 0.f)) {
                radiance[s.slot] += s.value;  // the boundary lies at the light itself
                continue;
            }
            next_.push(o, dir, 0.f, rest, uint32_t(next_state_.size()));
            next_state_.push_back(s);
        }
        std::swap(rays_, next_);
        std::swap(state_, next_state_);
    }
    state_.clear();
    stats.shadow_rays += traced;
    stats.add(Stage::Occlusion, traced, clock);
}

}  // namespace foton
