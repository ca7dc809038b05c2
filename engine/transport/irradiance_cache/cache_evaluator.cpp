#include "cache_evaluator.h"

#include <cmath>

#include "engine/core/rng.h"
#include "engine/core/rng_streams.h"
#include "engine/transport/common/next_event.h"
#include "engine/transport/common/shadow_batch.h"

namespace foton {

namespace {
// The cache's parameters from the scene's settings.
CacheParams cache_params(const CacheSettings& s) {
    CacheParams p;
    p.weight = s.ward_weight ? CacheWeight::Ward : CacheWeight::Notes;
    p.a = s.a;
    p.kappa = s.kappa;
    p.gradients = s.gradients;
    return p;
}

// Random dimensions of a record ray's hit: light choice, light position (3).
constexpr uint32_t kDimLight = 0;
}  // namespace

void CacheWorkspace::begin(std::size_t level_count, const Bounds3& bounds,
                           const CacheParams& params) {
    levels.resize(level_count);
    for (CacheLevelWork& l : levels) {
        l.pending.clear();
        l.requests.clear();
        l.rays.clear();
        l.L.clear();
        l.dist.clear();
        if (l.found)
            l.found->clear();
        else
            l.found = std::make_unique<IrradianceCache>(bounds, params);
    }
    lookup = {};
    trace = {};
}

CacheEvaluator::CacheEvaluator(const RenderContext& ctx, CacheSecondary mode,
                               PhotonRadiance photons, const RadianceAlongRays* path)
    : ctx_(ctx),
      mode_(mode),
      photons_(std::move(photons)),
      path_(path),
      levels_(mode == CacheSecondary::Cache ? ctx.settings.cache.levels : 1),
      strata_(HemisphereStrata::from_count(ctx.settings.cache.samples)),
      params_(cache_params(ctx.settings.cache)),
      bounds_(ctx.scene.bounds()) {}

bool CacheEvaluator::visibility_ray(const SurfacePoint& sp, const IrradianceRecord& r,
                                    kern::Ray1& ray) const {
    if (!ctx_.settings.cache.visibility) return false;
    // The notes' edge case: a record beyond an edge that p cannot see must not be used.
    // Both ends are lifted off their surfaces by a tenth of their distance, so that the
    // segment clears a curved surface between them (a chord of a sphere of radius R dips
    // d^2 / 8R below it) while a wall between them still blocks it.
    const float gap = length(r.p - sp.p);
    if (!(gap > sp.epsilon)) return false;
    const float lift = std::max(sp.epsilon, 0.1f * gap);
    const Vec3 a = sp.p + sp.ng * lift;
    const Vec3 b = r.p + r.n * lift;
    const Vec3 d = b - a;
    const float len = length(d);
    const Vec3 u = d * (1.f / len);
    ray = {a.x, a.y, a.z, u.x, u.y, u.z, 0.f, len};
    return true;
}

void CacheEvaluator::queue_pending(const SurfacePoint& sp, const warp::Frame& frame,
                                   const RGB& weight, uint32_t slot, uint64_t key,
                                   float path_length, CacheLevelWork& work) const {
    PendingLookup q;
    q.sp = sp;
    q.sp.ns = frame.n;
    q.s = frame.s;
    q.t = frame.t;
    q.r_min = ctx_.settings.cache.r_min_pixels * ctx_.scene.camera.footprint(path_length);
    q.path_length = path_length;
    q.slot = slot;
    q.weight = weight;
    q.key = key;
    work.pending.push_back(q);
}

void CacheEvaluator::queue_lookup(const SurfacePoint& sp, const warp::Frame& frame,
                                  const RGB& weight, uint32_t slot, uint64_t key, float path_length,
                                  CacheWorkspace& ws) const {
    enqueue(0, sp, frame, weight, slot, key, path_length, ws.batch, ws);
}

void CacheEvaluator::enqueue(uint32_t level, const SurfacePoint& sp, const warp::Frame& frame,
                             const RGB& weight, uint32_t slot, uint64_t key, float path_length,
                             CacheLookupBatch& b, CacheWorkspace& ws) const {
    CacheLookupBatch::Query q;
    q.sp = sp;
    q.sp.ns = frame.n;
    q.s = frame.s;
    q.t = frame.t;
    q.weight = weight;
    q.slot = slot;
    q.key = key;
    q.path_length = path_length;
    q.first = uint32_t(b.record.size());
    // The candidates in the order interpolate() takes them: the frozen cache's, then the
    // records this batch computed so far.
    const IrradianceCache& found = *ws.levels[level].found;
    caches_[level]->candidates(sp.p, frame.n, b.record, ws.lookup);
    q.frozen = uint32_t(b.record.size()) - q.first;
    found.candidates(sp.p, frame.n, b.record, ws.lookup);
    q.count = uint32_t(b.record.size()) - q.first;
    for (uint32_t c = q.first; c < q.first + q.count; ++c) {
        const IrradianceRecord& r = c < q.first + q.frozen ? caches_[level]->record(b.record[c])
                                                           : found.record(b.record[c]);
        kern::Ray1 ray;
        if (visibility_ray(sp, r, ray)) {
            b.ray.push_back(int32_t(b.rays.size()));
            b.rays.push({ray.ox, ray.oy, ray.oz}, {ray.dx, ray.dy, ray.dz}, ray.tmin, ray.tmax,
                        uint32_t(b.rays.size()));
        } else {
            b.ray.push_back(-1);
        }
    }
    b.queries.push_back(q);
}

void CacheEvaluator::serve_batch(uint32_t level, CacheLookupBatch& b, CacheWorkspace& ws,
                                 CacheCounters& st) const {
    if (!b.rays.empty()) ctx_.accel.occluded(b.rays, b.occluded, ws.trace);
    st.visibility_tests += b.rays.size();
    b.visible.resize(b.record.size());
    for (std::size_t c = 0; c < b.record.size(); ++c) {
        const bool blocked = b.ray[c] >= 0 && b.occluded[std::size_t(b.ray[c])];
        b.visible[c] = !blocked;
        st.visibility_rejections += blocked;
    }
    const IrradianceCache& found = *ws.levels[level].found;
    b.served.assign(b.queries.size(), 0);
    b.value.assign(b.queries.size(), RGB{0.f});
    for (std::size_t i = 0; i < b.queries.size(); ++i) {
        const CacheLookupBatch::Query& q = b.queries[i];
        IrradianceCache::Blend blend;
        ++st.lookups;
        const Vec3& n = q.sp.ns;
        caches_[level]->blend_visible(q.sp.p, n, b.record.data() + q.first,
                                      b.visible.data() + q.first, q.frozen, st, blend);
        found.blend_visible(q.sp.p, n, b.record.data() + q.first + q.frozen,
                            b.visible.data() + q.first + q.frozen, q.count - q.frozen, st, blend);
        RGB e;
        if (blend.finish(e, st)) {
            b.served[i] = 1;
            b.value[i] = q.weight * e;
            continue;
        }
        warp::Frame frame;
        frame.s = q.s;
        frame.t = q.t;
        frame.n = q.sp.ns;
        queue_pending(q.sp, frame, q.weight, q.slot, q.key, q.path_length, ws.levels[level]);
    }
}

void CacheEvaluator::serve_lookups(CacheWorkspace& ws, std::vector<RGB>& out, RenderStats& stats,
                                   StageClock& clock) const {
    CacheLookupBatch& b = ws.batch;
    if (b.queries.empty()) return;
    serve_batch(0, b, ws, ws.lookup);
    for (std::size_t i = 0; i < b.queries.size(); ++i)
        if (b.served[i]) out[b.queries[i].slot] += b.value[i];
    stats.add(Stage::CacheLookup, b.queries.size(), clock);
    b.clear();
}

void CacheEvaluator::resolve(CacheWorkspace& ws, std::vector<RGB>& out, RenderStats& stats) const {
    resolve_level(0, ws, out, stats);
    stats.trace.merge(ws.trace);
    stats.shadow_rays += ws.lookup.visibility_tests;
    stats.cache.merge(ws.lookup);
    ws.trace = {};
    ws.lookup = {};
}

void CacheEvaluator::pick_sites(CacheLevelWork& work, float f) const {
    const float factor = ctx_.settings.cache.r_max_factor;
    work.picked.assign(work.pending.size(), 0);
    std::vector<uint32_t> sites;
    for (uint32_t i = 0; i < work.pending.size(); ++i) {
        const PendingLookup& q = work.pending[i];
        const float spacing = f * factor * q.r_min;
        bool near = false;
        if (spacing > q.r_min)
            for (uint32_t j : sites) {
                const PendingLookup& o = work.pending[j];
                if (length_squared(o.sp.p - q.sp.p) < spacing * spacing &&
                    dot(o.sp.ns, q.sp.ns) > 0.9f) {
                    near = true;
                    break;
                }
            }
        if (near) continue;
        sites.push_back(i);
        work.picked[i] = 1;
        queue_record(work, i);
    }
}

void CacheEvaluator::queue_record(CacheLevelWork& work, uint32_t pending) const {
    // M x N stratified rays; those below the geometric surface see nothing (their radiance
    // stays 0, their distance infinite).
    const CacheSettings& cs = ctx_.settings.cache;
    const PendingLookup& q = work.pending[pending];
    warp::Frame frame;
    frame.s = q.s;
    frame.t = q.t;
    frame.n = q.sp.ns;
    const uint32_t first = uint32_t(work.L.size());
    const uint32_t count = strata_.count();
    work.L.resize(work.L.size() + count, RGB{0.f});
    work.dist.resize(work.dist.size() + count, kInfinity);
    const float tmax =
        mode_ == CacheSecondary::Occlusion && cs.ao_distance > 0.f ? cs.ao_distance : kInfinity;
    for (uint32_t j = 0; j < strata_.m; ++j)
        for (uint32_t k = 0; k < strata_.n; ++k) {
            const uint32_t i = j * strata_.n + k;
            const Vec3 wi = frame.to_world(strata_.direction(
                j, k,
                {rng::uniform(ctx_.seed, q.key, i, 0), rng::uniform(ctx_.seed, q.key, i, 1)}));
            if (dot(wi, q.sp.ng) <= 0.f) continue;
            work.rays.push(offset_origin(q.sp, wi), wi, 0.f, tmax, first + i);
        }
    work.requests.push_back({pending, first});
}

void CacheEvaluator::resolve_level(uint32_t level, CacheWorkspace& ws, std::vector<RGB>& out,
                                   RenderStats& stats) const {
    CacheLevelWork& work = ws.levels[level];
    const CacheSettings& cs = ctx_.settings.cache;
    const RadiusRule rule = cs.minimum_radius ? RadiusRule::Minimum : RadiusRule::Harmonic;
    for (int round = 0; !work.pending.empty(); ++round) {
        if (round > 0) {
            // What this batch's records now serve (counted as interpolated, not as lookups),
            // in the order they wait; the rest wait again, in that order.
            CacheLookupBatch& b = work.lookups;
            b.clear();
            const std::vector<PendingLookup> waiting = std::move(work.pending);
            work.pending.clear();
            for (const PendingLookup& q : waiting) {
                warp::Frame frame;
                frame.s = q.s;
                frame.t = q.t;
                frame.n = q.sp.ns;
                enqueue(level, q.sp, frame, q.weight, q.slot, q.key, q.path_length, b, ws);
            }
            CacheCounters st;
            serve_batch(level, b, ws, st);
            for (std::size_t i = 0; i < b.queries.size(); ++i)
                if (b.served[i]) out[b.queries[i].slot] += b.value[i];
            b.clear();
            st.lookups = 0;
            ws.lookup.merge(st);
            if (work.pending.empty()) break;
        }
        pick_sites(work, std::ldexp(1.f, -round));
        evaluate(level, ws, stats);
        // Lookups of the next level that this round's rays made, served first: their
        // irradiance is part of what those rays see.
        if (level + 1 < levels_) resolve_level(level + 1, ws, work.L, stats);
        StageClock clock;
        for (const CacheRequest& r : work.requests) {
            const PendingLookup& q = work.pending[r.pending];
            const IrradianceRecord rec =
                build_record(q.sp.p, q.s, q.t, q.sp.ns, strata_, &work.L[r.first],
                             &work.dist[r.first], rule, q.r_min, q.r_min * cs.r_max_factor);
            out[q.slot] += q.weight * rec.e;
            work.found->insert(rec);
        }
        stats.cache_records += work.requests.size();
        stats.add(Stage::CacheRecords, work.requests.size(), clock);
        work.requests.clear();
        work.L.clear();
        work.dist.clear();
        std::size_t kept = 0;
        for (std::size_t i = 0; i < work.pending.size(); ++i)
            if (!work.picked[i]) work.pending[kept++] = work.pending[i];
        work.pending.resize(kept);
    }
}

void CacheEvaluator::evaluate(uint32_t level, CacheWorkspace& ws, RenderStats& stats) const {
    CacheLevelWork& work = ws.levels[level];
    StageClock clock;
    stats.secondary_rays += work.rays.size();
    if (mode_ == CacheSecondary::Path) {
        // Path tracing onwards, keyed per ray.
        if (!ws.path) ws.path = path_->make_workspace();
        std::vector<uint64_t>& keys = ws.path_keys;
        keys.resize(work.L.size());
        for (std::size_t i = 0; i < work.L.size(); ++i)
            keys[i] = rng::hash(work.pending[work.requests[i / strata_.count()].pending].key,
                                i % strata_.count(), kCacheStream, 1);
        path_->radiance_along(work.rays, keys, *ws.path, work.L, work.dist.data(), stats);
        work.rays.clear();
        return;
    }
    if (mode_ == CacheSecondary::Occlusion) {
        // The ambient radiance from every direction not blocked within ao_distance.
        const RGB sky =
            ctx_.scene.ambient.radiance().is_black() ? RGB{1.f} : ctx_.scene.ambient.radiance();
        HitBatch& hits = ws.gather.hits;
        ctx_.accel.intersect(work.rays, hits, stats.trace);
        for (std::size_t i = 0; i < work.rays.size(); ++i) {
            const uint32_t id = work.rays.id[i];
            if (hits.geom[i] == kNoHit)
                work.L[id] = sky;
            else
                work.dist[id] = hits.t[i];
        }
        stats.add(Stage::Intersect, work.rays.size(), clock);
        work.rays.clear();
        return;
    }
    // Direct, photon or cache: the rays' first diffuse hits, through specular chains.
    GatherBuffers& g = ws.gather;
    std::swap(g.rays, work.rays);
    work.rays.clear();
    g.weight.assign(g.rays.size(), RGB{1.f});
    ws.shadow.clear();
    ws.shadow_value.clear();
    const bool deeper = mode_ == CacheSecondary::Cache && level + 1 < levels_;
    // The next level's lookups wait for one batch of visibility rays after the trace; so that
    // L sums in the ray-by-ray walk's order, the additions made meanwhile are logged.
    CacheLookupBatch* const next = deeper ? &ws.levels[level + 1].lookups : nullptr;
    if (next) next->clear();
    work.adds.clear();
    const std::size_t traced = trace_gather(
        ctx_.scene, ctx_.accel, g, work.dist.data(), stats,
        [&](uint32_t id, const RGB& w, const SurfacePoint& sp, const Material& m, const Vec3& d) {
            if (mode_ == CacheSecondary::Photon) {
                work.L[id] += w * photons_(sp, m, d);
                return;
            }
            const warp::Frame frame = sp.frame();
            const PendingLookup& q = work.pending[work.requests[id / strata_.count()].pending];
            const uint64_t key = rng::hash(q.key, id % strata_.count(), kCacheStream, 2);
            DirectSample ds;
            if (sample_direct(ctx_.lights, ShadingPoint(sp, m, d, w, id, 0, key),
                              rng::uniform(ctx_.seed, key, kDimLight, 0),
                              {rng::uniform(ctx_.seed, key, kDimLight + 1, 0),
                               rng::uniform(ctx_.seed, key, kDimLight + 2, 0)},
                              rng::uniform(ctx_.seed, key, kDimLight + 3, 0), ds))
                queue_direct(ds, id, ws.shadow, ws.shadow_value);
            RGB rho;
            if (next && m.bsdf.lambert_albedo(rho) && !rho.is_black()) {
                work.adds.push_back({id, int32_t(next->queries.size()), RGB{0.f}});
                enqueue(level + 1, sp, frame, w * rho * kInvPi, id,
                        rng::hash(key, kCacheStream, 3, 0), q.path_length + length(sp.p - q.sp.p),
                        *next, ws);
            }
        },
        [&](uint32_t slot, const RGB& v) {
            if (next)
                work.adds.push_back({slot, -1, v});
            else
                work.L[slot] += v;
        });
    if (next) {
        serve_batch(level + 1, *next, ws, ws.lookup);
        for (const LoggedAdd& a : work.adds) {
            if (a.query < 0)
                work.L[a.slot] += a.value;
            else if (next->served[std::size_t(a.query)])
                work.L[a.slot] += next->value[std::size_t(a.query)];
        }
        next->clear();
        work.adds.clear();
    }
    stats.add(Stage::FinalGather, traced, clock);
    resolve_shadow_rays(ctx_.accel, ws.shadow, ws.shadow_value, ws.occluded, work.L, stats, clock);
}

}  // namespace foton
