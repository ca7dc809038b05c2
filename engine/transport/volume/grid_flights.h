#pragma once
// A bounce's free flights through grid media as one batch: delta tracking round by round,
// every live flight's next tentative collision found at once by the majorant march kernel
// (kernels/majorant_march.h, W flights per register), then each collision decided one by one
// (the density there, absorption, scattering or a null collision). Each flight draws its
// numbers in the order delta_track_grid (common/medium_tracking.h) draws them, and the
// kernel equals its scalar twin bit for bit, so a batched flight ends exactly where the
// one-at-a-time flight would; `simd = false` runs the twin, for measuring the kernel.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "engine/core/math.h"
#include "engine/core/ray_batch.h"
#include "engine/core/rgb.h"
#include "engine/scene/scene.h"
#include "engine/transport/common/medium_tracking.h"

namespace foton {

class GridFlights {
  public:
    void clear();
    bool empty() const { return slot_.empty(); }
    std::size_t size() const { return slot_.size(); }
    // A flight of path `slot` in grid medium `medium` along o + t d over [0, t_end), of a path
    // with throughput beta; its result is result(index) after run().
    void add(uint32_t slot, int32_t medium, const Vec3& o, const Vec3& d, float t_end,
             const RGB& beta);
    // Tracks every flight to its end; u(slot) draws the path's next uniform number.
    template <class Uniform>
    void run(const Scene& scene, bool simd, Uniform&& u);
    const FreeFlight& result(std::size_t i) const { return result_[i]; }
    // The flights of a traced batch: every ray whose path (rays.id) is in a grid medium flies
    // to its hit (or to infinity); flight_of[i] is ray i's flight (-1: none). u(slot) as run().
    template <class Uniform>
    void track_batch(const Scene& scene, const RayBatch& rays, const HitBatch& hits,
                     const std::vector<int32_t>& medium, const std::vector<RGB>& beta, bool simd,
                     std::vector<int32_t>& flight_of, Uniform&& u);

  private:
    // One round for the live flights of medium `medium`: their next tentative collisions.
    void march(const Scene& scene, int32_t medium, bool simd);
    // Flight i's collision at t_hit_[i] with majorant maj_[i]: true while it goes on (null).
    template <class Uniform>
    bool collide(const Medium& m, std::size_t i, Uniform&& u);

    std::vector<uint32_t> slot_;
    std::vector<int32_t> medium_;
    std::vector<Vec3> o_, d_;
    std::vector<float> t_end_;
    std::vector<RGB> beta_;
    std::vector<FreeFlight> result_;
    std::vector<float> t_;  // where each live flight stands
    std::vector<uint32_t> live_, next_live_;
    std::vector<int32_t> media_;  // the grid media of a round's live flights
    // The kernel's SoA of one round (the live flights of one medium), and which flight each
    // row is.
    std::vector<float> tau_;  // per flight: the optical depth this round spends
    std::vector<float> ox_, oy_, oz_, dx_, dy_, dz_, te_, tau_rows_, th_, maj_;
    std::vector<uint8_t> hit_;
    std::vector<uint32_t> row_;
    // Per flight: this round's tentative collision, its majorant, whether there is one.
    std::vector<float> t_hit_, maj_of_;
    std::vector<uint8_t> collided_;
};

template <class Uniform>
bool GridFlights::collide(const Medium& m, std::size_t i, Uniform&& u) {
    FreeFlight& f = result_[i];
    const float t = t_hit_[i];
    if (++f.collisions > kMaxCollisions) {
        f.event = FreeFlight::Event::Absorb;
        return false;
    }
    const Vec3 p = o_[i] + d_[i] * t;
    const MediumPoint c = m.at(p);
    if (m.emits()) f.emitted += f.weight * c.sigma_a * m.emission_at(p) * (1.f / maj_of_[i]);
    auto draw = [&] { return u(slot_[i]); };
    if (!choose_collision(f, beta_[i], c.sigma_a, c.sigma_s, maj_of_[i], t, draw)) return false;
    t_[i] = t;
    return true;
}

template <class Uniform>
void GridFlights::track_batch(const Scene& scene, const RayBatch& rays, const HitBatch& hits,
                              const std::vector<int32_t>& medium, const std::vector<RGB>& beta,
                              bool simd, std::vector<int32_t>& flight_of, Uniform&& u) {
    flight_of.assign(rays.size(), -1);
    clear();
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const uint32_t slot = rays.id[i];
        const int32_t mi = medium[slot];
        if (mi == kNoMedium || scene.media[std::size_t(mi)].homogeneous()) continue;
        flight_of[i] = int32_t(size());
        add(slot, mi, rays.origin(i), rays.direction(i),
            hits.geom[i] == kNoHit ? kInfinity : hits.t[i], beta[slot]);
    }
    if (!empty()) run(scene, simd, u);
}

template <class Uniform>
void GridFlights::run(const Scene& scene, bool simd, Uniform&& u) {
    live_.clear();
    for (std::size_t i = 0; i < slot_.size(); ++i) live_.push_back(uint32_t(i));
    while (!live_.empty()) {
        // Each live flight's optical depth to spend, in flight order (the numbers' order).
        tau_.resize(slot_.size());
        for (uint32_t i : live_) tau_[i] = -std::log1p(-u(slot_[i]));
        // The media of this round's flights (a scene has few), each marched as one batch.
        media_.clear();
        for (uint32_t i : live_)
            if (std::find(media_.begin(), media_.end(), medium_[i]) == media_.end())
                media_.push_back(medium_[i]);
        for (int32_t m : media_) march(scene, m, simd);
        next_live_.clear();
        for (uint32_t i : live_) {
            if (!collided_[i]) continue;  // passed: the weight so far
            if (collide(scene.media[std::size_t(medium_[i])], i, u)) next_live_.push_back(i);
        }
        std::swap(live_, next_live_);
    }
}

// The flight of batch entry r, in medium mi (not vacuum), of a path with throughput beta: the
// batched grid flight's result (track_batch's flight_of), or a homogeneous medium's sampled
// analytically now.
template <class Uniform>
FreeFlight flight_of_entry(const Scene& scene, const GridFlights& flights,
                           const std::vector<int32_t>& flight_of, const RayBatch& rays,
                           const HitBatch& hits, std::size_t r, int32_t mi, const RGB& beta,
                           Uniform&& u) {
    if (flight_of[r] >= 0) return flights.result(std::size_t(flight_of[r]));
    const float t_end = hits.geom[r] == kNoHit ? kInfinity : hits.t[r];
    return free_flight(scene.media[std::size_t(mi)], rays.origin(r), rays.direction(r), t_end, beta,
                       FreeFlightSampling::Analytic, u);
}

}  // namespace foton
