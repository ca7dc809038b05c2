#pragma once
// Participating media on the subpaths of bdpt and vcm. Each path knows its medium; a bounce's
// free flights are sampled as the volumetric path tracer samples them (common/
// medium_tracking.h; grid media as one batch, volume/grid_flights.h), each with the path's
// own counter of numbers; interfaces are passed without a vertex; and every join (a light
// sample, a connection, the join to the camera) is a shadow ray through the media on the way
// (common/medium_shadow.h). A medium vertex is where a flight scattered: the Henyey-Greenstein
// phase function stands for its BSDF, it has no cosines (1 in every change of measure) and
// no merge happens there (merging estimates a surface density; vcm_mis.h).
//
// The MIS weights take the directional densities and the geometry, not the densities of the
// sampled distances (as pbrt-v3's bdpt): those are transmittances no strategy knows exactly
// in a grid medium. Each path's weights still sum to one over the strategies that can make
// it, so the estimate stays unbiased; only the choice among strategies is less informed.
#include <cstdint>
#include <vector>

#include "engine/core/rng.h"
#include "engine/core/rng_streams.h"
#include "engine/transport/common/medium_shadow.h"
#include "engine/transport/volume/grid_flights.h"

namespace foton {

struct SubpathMedia {
    bool on = false;                  // the scene has media: all of the below is in use
    std::vector<int32_t> medium;      // per slot: where its ray travels
    std::vector<uint32_t> crossings;  // interfaces passed
    std::vector<uint32_t> draws;      // free-flight numbers drawn
    std::vector<uint64_t> key;        // the path's key for them
    std::vector<Vec3> from;           // the last vertex: MIS distances run from it
    GridFlights flights;
    std::vector<int32_t> flight_of;
    uint64_t prefix = 0;

    void reset(bool media, uint64_t seed, RandomStream stream, uint32_t count) {
        on = media;
        if (!on) return;
        prefix = rng::stream_prefix(seed, stream);
        medium.assign(count, kNoMedium);
        crossings.assign(count, 0);
        draws.assign(count, 0);
        key.assign(count, 0);
        from.assign(count, Vec3{});
    }
    float number(uint32_t slot) { return rng::uniform_from(prefix, key[slot], draws[slot]++); }
    // The bounce's grid flights, all at once, before its rays are shaded.
    void track(const Scene& scene, const RayBatch& rays, const HitBatch& hits,
               const std::vector<RGB>& beta, bool simd) {
        flights.track_batch(scene, rays, hits, medium, beta, simd, flight_of,
                            [&](uint32_t slot) { return number(slot); });
    }
    // How ray r's flight ended for its path: gone (absorbed, or no throughput left),
    // scattered in the medium at `t` (the vertex is the caller's), or passed to what the ray
    // hit. Outside media every ray passes; beta takes the flight's weight.
    enum class FlightEnd { Gone, Scattered, Passed };
    FlightEnd fly(const Scene& scene, const RayBatch& rays, const HitBatch& hits, std::size_t r,
                  RGB& beta, float& t) {
        const uint32_t slot = rays.id[r];
        if (!on || medium[slot] == kNoMedium) return FlightEnd::Passed;
        const FreeFlight f = flight_of_entry(scene, flights, flight_of, rays, hits, r, medium[slot],
                                             beta, [&] { return number(slot); });
        if (f.event == FreeFlight::Event::Absorb) return FlightEnd::Gone;
        beta *= f.weight;
        if (beta.is_black()) return FlightEnd::Gone;
        t = f.t;
        return f.event == FreeFlight::Event::Scatter ? FlightEnd::Scattered : FlightEnd::Passed;
    }
};

// A batch's joins: shadow rays that add a value where they arrive, tested for occlusion alone
// in a scene without media (the engine's occlusion kernel), else traced through the media.
class JoinRays {
  public:
    void clear() {
        plain_.clear();
        media_.clear();
        value_.clear();
        slot_.clear();
        layer_.clear();
    }
    bool empty() const { return value_.empty(); }
    std::size_t size() const { return value_.size(); }
    // A join in `medium` (ignored without media) for slot `slot` and strategy layer `layer`;
    // `key` keys ratio tracking.
    void push(bool media, const ShadowRay& r, int32_t medium, uint32_t slot, const RGB& value,
              uint32_t layer, uint64_t key) {
        const uint32_t i = uint32_t(value_.size());
        if (media)
            media_.push(r.origin, r.dir, r.tmax, medium, i, value, key);
        else
            plain_.push(r.origin, r.dir, 0.f, r.tmax, i);
        value_.push_back(value);
        slot_.push_back(slot);
        layer_.push_back(layer);
    }
    // Calls add(slot, layer, value) for every join that arrives, in the order they were
    // pushed.
    template <class Add>
    void resolve(bool media, const Scene& scene, const Intersector& accel, uint64_t seed,
                 RenderStats& stats, StageClock& clock, Add&& add) {
        if (empty()) return;
        if (media) {
            arrived_.assign(value_.size(), RGB{0.f});
            media_.resolve(scene, accel, TransmittanceEstimator::Exact, seed, arrived_, stats,
                           clock);
            for (std::size_t i = 0; i < arrived_.size(); ++i)
                if (!arrived_[i].is_black()) add(slot_[i], layer_[i], arrived_[i]);
            return;
        }
        accel.occluded(plain_, occluded_, stats.trace);
        stats.shadow_rays += plain_.size();
        stats.add(Stage::Occlusion, plain_.size(), clock);
        for (std::size_t i = 0; i < plain_.size(); ++i)
            if (!occluded_[i]) add(slot_[i], layer_[i], value_[i]);
    }

  private:
    RayBatch plain_;
    MediumShadowRays media_;
    std::vector<RGB> value_, arrived_;
    std::vector<uint32_t> slot_, layer_;
    std::vector<uint8_t> occluded_;
};

}  // namespace foton
