#include "adaptive_photons.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "engine/core/rng.h"
#include "engine/core/rng_streams.h"
#include "engine/core/thread_clock.h"

namespace foton {

namespace {

// The acceptance rate the mutation's reach is steered to (Hachisuka and Jensen 2011, after
// the optimal rate of random-walk Metropolis in many dimensions).
constexpr float kTargetAcceptance = 0.234f;
constexpr float kMinDelta = 1e-5f, kMaxDelta = 0.5f;
constexpr int64_t kCellRange = int64_t(1) << 20;  // cells per axis each side, clamped

}  // namespace

int64_t VisiblePointGrid::cell(float v, float lo) const {
    const double c = std::floor(double(v - lo) / double(cell_));
    return int64_t(std::clamp(c, 0.0, double(2 * kCellRange - 1)));
}

uint64_t VisiblePointGrid::key(int64_t x, int64_t y, int64_t z) const {
    return (uint64_t(x) << 42) | (uint64_t(y) << 21) | uint64_t(z);
}

void VisiblePointGrid::build(const std::vector<SppmPixel>& pixels) {
    keys_.clear();
    points_.clear();
    float rmax = 0.f;
    Bounds3 b;
    for (const SppmPixel& px : pixels)
        if (px.valid && px.radius > 0.f) {
            rmax = std::max(rmax, px.radius);
            b.extend(px.p);
        }
    if (b.empty()) return;
    cell_ = rmax;
    lo_ = b.lo - Vec3{rmax, rmax, rmax};
    std::vector<std::pair<uint64_t, Point>> items;
    for (const SppmPixel& px : pixels)
        if (px.valid && px.radius > 0.f)
            items.push_back({key(cell(px.p.x, lo_.x), cell(px.p.y, lo_.y), cell(px.p.z, lo_.z)),
                             {px.p.x, px.p.y, px.p.z, px.radius * px.radius}});
    std::stable_sort(items.begin(), items.end(),
                     [](const auto& a, const auto& c) { return a.first < c.first; });
    for (const auto& [k, p] : items) {
        keys_.push_back(k);
        points_.push_back(p);
    }
}

bool VisiblePointGrid::sees(const Vec3& p) const {
    if (keys_.empty()) return false;
    const int64_t cx = cell(p.x, lo_.x), cy = cell(p.y, lo_.y), cz = cell(p.z, lo_.z);
    // A cell is as wide as the largest radius: every point that can see p is in p's cell or
    // a neighbour.
    for (int64_t x = std::max<int64_t>(0, cx - 1); x <= cx + 1; ++x)
        for (int64_t y = std::max<int64_t>(0, cy - 1); y <= cy + 1; ++y)
            for (int64_t z = std::max<int64_t>(0, cz - 1); z <= cz + 1; ++z) {
                const uint64_t k = key(x, y, z);
                auto it = std::lower_bound(keys_.begin(), keys_.end(), k);
                for (std::size_t i = std::size_t(it - keys_.begin());
                     i < keys_.size() && keys_[i] == k; ++i) {
                    const Point& q = points_[i];
                    const float dx = p.x - q.x, dy = p.y - q.y, dz = p.z - q.z;
                    if (dx * dx + dy * dy + dz * dz < q.r2) return true;
                }
            }
    return false;
}

AdaptivePhotonTracer::AdaptivePhotonTracer(const PhotonTracer& tracer, uint64_t seed,
                                           uint32_t max_depth, bool unscaled_roulette)
    : tracer_(tracer),
      seed_(seed),
      max_depth_(max_depth),
      dims_(photon_dims(max_depth)),
      unscaled_(unscaled_roulette) {}

void AdaptivePhotonTracer::trace_paths(uint64_t pass, const std::vector<float>& numbers,
                                       uint32_t count, const VisiblePointGrid& grid,
                                       PhotonWorkspace& ws, PhotonMap& out,
                                       std::vector<uint32_t>& by, std::vector<uint8_t>& visible,
                                       RenderStats& stats) const {
    PhotonPassSettings s;
    s.kind = PhotonMapKind::Global;
    s.emitted = count;
    s.max_depth = max_depth_;
    s.unscaled_roulette = unscaled_;
    s.pass = pass;
    s.numbers = numbers.data();
    s.number_dims = dims_;
    s.stored_by = &by;
    out.clear();
    by.clear();
    tracer_.trace(s, 0, count, ws, out, nullptr, stats);
    visible.assign(count, 0);
    for (std::size_t j = 0; j < out.size(); ++j)
        if (!(out.flags(j) & kPhotonDirect) && grid.sees(out.position(j))) visible[by[j]] = 1;
}

void AdaptivePhotonTracer::run_chunk(uint64_t pass, std::size_t c, const VisiblePointGrid& grid,
                                     PhotonWorkspace& ws, PhotonMap& out, AdaptiveStats& st,
                                     RenderStats& stats) {
    std::vector<AdaptiveChain>& chains = chunks_[c];
    const uint64_t pass_seed = seed_ + pass * 0x9e3779b97f4a7c15ull;
    // A path seen by the last pass's points may not be seen by this pass's.
    for (AdaptiveChain& ch : chains) {
        bool seen = false;
        for (std::size_t j = 0; j < ch.photons.size() && !seen; ++j)
            seen = !(ch.photons.flags(j) & kPhotonDirect) && grid.sees(ch.photons.position(j));
        if (!seen) {
            ch.u.clear();
            ch.photons.clear();
        }
    }
    std::vector<float> numbers(std::size_t(kChains) * dims_);
    std::vector<uint32_t> by, which;
    std::vector<uint8_t> visible, take(kChains);
    PhotonMap traced, kept;
    uint64_t recorded = 0, uniform_visible = 0;
    // Moves the traced paths k (of chains which[k]) that `take` marks into their chains.
    auto adopt = [&](const std::vector<uint32_t>& chain_of) {
        for (uint32_t k = 0; k < chain_of.size(); ++k)
            if (take[k]) {
                AdaptiveChain& ch = chains[chain_of[k]];
                ch.u.assign(numbers.begin() + std::ptrdiff_t(k) * dims_,
                            numbers.begin() + std::ptrdiff_t(k + 1) * dims_);
                ch.photons.clear();
            }
        for (std::size_t j = 0; j < traced.size(); ++j)
            if (take[by[j]]) chains[chain_of[by[j]]].photons.push_from(traced, j, 1.f);
    };
    std::vector<uint32_t> all(kChains);
    std::iota(all.begin(), all.end(), 0u);
    for (uint32_t step = 0; step < kSteps; ++step) {
        // A uniform proposal for every chain: taken where visible.
        for (uint32_t k = 0; k < kChains; ++k) {
            const uint64_t index = (uint64_t(c) * kSteps + step) * kChains + k;
            for (uint32_t d = 0; d < dims_; ++d)
                numbers[std::size_t(k) * dims_ + d] =
                    rng::uniform(pass_seed, kAdaptivePhotonStream, index, d);
        }
        trace_paths(pass, numbers, kChains, grid, ws, traced, by, visible, stats);
        for (uint32_t k = 0; k < kChains; ++k) {
            take[k] = visible[k];
            uniform_visible += visible[k];
        }
        adopt(all);
        // The other chains with a path propose a mutation of it.
        which.clear();
        for (uint32_t k = 0; k < kChains; ++k)
            if (!visible[k] && !chains[k].u.empty()) which.push_back(k);
        for (uint32_t m = 0; m < which.size(); ++m) {
            const AdaptiveChain& ch = chains[which[m]];
            const uint64_t index = (uint64_t(c) * kSteps + step) * kChains + which[m];
            for (uint32_t d = 0; d < dims_; ++d) {
                float v =
                    ch.u[d] +
                    ch.delta *
                        (2.f * rng::uniform(pass_seed, kAdaptiveMutationStream, index, d) - 1.f);
                v -= std::floor(v);
                numbers[std::size_t(m) * dims_ + d] = std::min(v, 0x1.fffffep-1f);
            }
        }
        if (!which.empty()) {
            trace_paths(pass, numbers, uint32_t(which.size()), grid, ws, traced, by, visible,
                        stats);
            for (uint32_t m = 0; m < which.size(); ++m) {
                take[m] = visible[m];
                AdaptiveChain& ch = chains[which[m]];
                ++ch.mutations;
                ch.delta += (float(visible[m]) - kTargetAcceptance) / float(ch.mutations);
                ch.delta = std::clamp(ch.delta, kMinDelta, kMaxDelta);
                ++st.mutations;
                st.accepted += visible[m];
            }
            adopt(which);
        }
        // Every chain with a path stores it once more.
        for (const AdaptiveChain& ch : chains) {
            if (ch.u.empty()) continue;
            ++recorded;
            kept.append(ch.photons);
        }
    }
    st.uniform += uint64_t(kSteps) * kChains;
    st.uniform_visible += uniform_visible;
    st.recorded += recorded;
    out = std::move(kept);
}

PhotonMap AdaptivePhotonTracer::run(uint64_t pass, uint64_t emitted,
                                    const VisiblePointGrid& visible, RenderStats& stats,
                                    const std::atomic<bool>* cancel, const Cluster* cluster) {
    const uint64_t per_chunk = uint64_t(kChains) * kSteps;
    const std::size_t chunks =
        std::size_t(std::max<uint64_t>(1, (emitted + per_chunk - 1) / per_chunk));
    if (chunks_.size() != chunks) chunks_.assign(chunks, std::vector<AdaptiveChain>(kChains));
    const Cluster& ranks = cluster_or_solo(cluster);
    const Share mine = share_of(chunks, ranks);
    std::vector<PhotonMap> parts(chunks);
    std::vector<AdaptiveStats> part_stats(chunks);
    tbb::enumerable_thread_specific<PhotonWorkspace> workspaces;
    tbb::enumerable_thread_specific<RenderStats> st;
    BusyTime* const busy = ThreadClock::for_chunks();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(mine.begin, mine.end, 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          const ThreadClock clock(busy);
                          for (std::size_t c = r.begin(); c != r.end(); ++c) {
                              if (cancel && cancel->load(std::memory_order_relaxed)) return;
                              run_chunk(pass, c, visible, workspaces.local(), parts[c],
                                        part_stats[c], st.local());
                          }
                      });
    StageClock clock;
    AdaptiveStats pass_stats;
    for (const AdaptiveStats& a : part_stats) {
        pass_stats.uniform += a.uniform;
        pass_stats.uniform_visible += a.uniform_visible;
        pass_stats.mutations += a.mutations;
        pass_stats.accepted += a.accepted;
        pass_stats.recorded += a.recorded;
    }
    // The pass's estimate: Z (the visible fraction of its uniform paths, over every rank's
    // chunks) times the mean of the paths its chains stored.
    uint64_t seen = pass_stats.uniform_visible, recorded = pass_stats.recorded;
    if (ranks.distributed()) {
        seen = recorded = 0;
        for (const uint64_t v : ranks.all_sizes(pass_stats.uniform_visible)) seen += v;
        for (const uint64_t v : ranks.all_sizes(pass_stats.recorded)) recorded += v;
    }
    const double z = double(seen) / double(uint64_t(chunks) * per_chunk);
    const float scale = recorded > 0 ? float(z / double(recorded)) : 0.f;
    PhotonMap map;
    std::size_t total = 0;
    for (const PhotonMap& p : parts) total += p.size();
    map.reserve(total);
    for (const PhotonMap& p : parts)
        for (std::size_t j = 0; j < p.size(); ++j) map.push_from(p, j, scale);
    if (ranks.distributed()) map.all_gather(ranks);
    totals_.uniform += pass_stats.uniform;
    totals_.uniform_visible += pass_stats.uniform_visible;
    totals_.mutations += pass_stats.mutations;
    totals_.accepted += pass_stats.accepted;
    totals_.recorded += pass_stats.recorded;
    for (const RenderStats& l : st) stats.merge(l);
    stats.add(Stage::PhotonStore, total, clock);
    return map;
}

}  // namespace foton
