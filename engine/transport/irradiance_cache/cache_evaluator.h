#pragma once
// The irradiance cache at work inside a camera wavefront. A lookup at a diffuse point
// interpolates the records of its level's frozen cache and of the records the current batch
// has computed so far, or waits. At the end of the batch the waiting points are served in
// rounds, the batch's own version of the notes' hierarchical order: each round picks new
// record sites among them, spaced by R_max in the first round and by half as much in each
// next one (every remaining point in the last, when the spacing reaches R_min), computes
// those records together (their M x N hemisphere rays traced as batches and evaluated by the
// secondary mode, scene.h CacheSecondary), and lets the rest interpolate from them. Without
// the rounds a batch could not reuse its own records, and with secondary = cache, where one
// record's rays make hundreds of lookups in the next level, the work would multiply by the
// ray count at every level. The new records stay in the workspace: the fill pass
// (cache_fill.h) merges them in a fixed order.
#include <functional>
#include <memory>
#include <vector>

#include "engine/accel/intersector.h"
#include "engine/core/warp.h"
#include "engine/scene/light_set.h"
#include "engine/transport/common/camera_integrator.h"
#include "engine/transport/common/gather_trace.h"
#include "engine/transport/common/radiance_along_rays.h"
#include "engine/transport/common/surface.h"
#include "engine/transport/irradiance_cache/irradiance_cache.h"
#include "engine/transport/run/render_context.h"

namespace foton {

// A lookup no record could serve yet.
struct PendingLookup {
    SurfacePoint sp;
    Vec3 s, t;                // with sp.ns, the frame of its record
    float r_min = 0.f;        // R_min there (pixel footprints along the path)
    float path_length = 0.f;  // from the camera
    uint32_t slot = 0;        // where weight * E goes
    RGB weight;               // radiance per unit of irradiance (beta * rho / pi)
    uint64_t key = 0;         // of its random numbers
};

// A record being computed: a picked lookup and its strata in L / dist.
struct CacheRequest {
    uint32_t pending = 0;
    uint32_t first = 0;
};

// Lookups of one level served together: each one's candidate records (of the level's frozen
// cache, then of the batch's own), and one batch of visibility rays for all of them. The
// camera paths' level-0 lookups of a bounce, and a record's rays' lookups in the next level.
struct CacheLookupBatch {
    struct Query {
        SurfacePoint sp;
        Vec3 s, t;
        RGB weight;
        uint32_t slot = 0;
        uint64_t key = 0;
        float path_length = 0.f;
        uint32_t first = 0, frozen = 0, count = 0;  // its candidates: [first, first + count),
                                                    // the first `frozen` of the frozen cache
    };
    std::vector<Query> queries;
    std::vector<uint32_t> record;  // candidate records
    std::vector<uint8_t> visible;  // per candidate
    std::vector<int32_t> ray;      // per candidate: its visibility ray, or -1 for none
    RayBatch rays;
    std::vector<uint8_t> occluded;
    std::vector<uint8_t> served;  // per query, once served: the cache could interpolate
    std::vector<RGB> value;       // per query served: weight * E
    void clear() {
        queries.clear();
        record.clear();
        visible.clear();
        ray.clear();
        rays.clear();
        served.clear();
        value.clear();
    }
};

// An addition to a record ray's radiance, kept in the order the ray-by-ray walk made it: a
// value, or (query >= 0) the result of a deeper lookup served later as a batch.
struct LoggedAdd {
    uint32_t slot;
    int32_t query;
    RGB value;
};

// One cache level's work in the current batch.
struct CacheLevelWork {
    std::vector<PendingLookup> pending;
    std::vector<CacheRequest> requests;  // this round's records
    RayBatch rays;                       // their hemisphere rays; id = index into L and dist
    std::vector<RGB> L;
    std::vector<float> dist;
    std::unique_ptr<IrradianceCache> found;  // the records this batch computed
    std::vector<uint8_t> picked;
    CacheLookupBatch lookups;     // this level's lookups (re-interpolation; from the level above)
    std::vector<LoggedAdd> adds;  // additions to L while its rays are traced (deeper lookups)
};

struct CacheWorkspace {
    std::vector<CacheLevelWork> levels;
    CacheLookupBatch batch;
    GatherBuffers gather;
    RayBatch shadow;
    std::vector<RGB> shadow_value;
    std::vector<uint8_t> occluded;
    std::unique_ptr<IntegratorWorkspace> path;  // secondary = path
    std::vector<uint64_t> path_keys;
    CacheCounters lookup;
    TraceCounters trace;  // visibility rays
    // Empties every level (found records included) for a new batch.
    void begin(std::size_t level_count, const Bounds3& bounds, const CacheParams& params);
};

class CacheEvaluator {
  public:
    // What a record ray sees at a non-delta hit in `photon` mode.
    using PhotonRadiance =
        std::function<RGB(const SurfacePoint& sp, const Material& m, const Vec3& dir)>;
    // `photons` is needed by secondary = photon, `path` by secondary = path.
    CacheEvaluator(const RenderContext& ctx, CacheSecondary mode, PhotonRadiance photons,
                   const RadianceAlongRays* path);
    // The frozen caches, one per level (levels() of them).
    void set_caches(std::vector<const IrradianceCache*> caches) { caches_ = std::move(caches); }
    uint32_t levels() const { return levels_; }
    CacheSecondary mode() const { return mode_; }
    const CacheParams& params() const { return params_; }
    const Bounds3& bounds() const { return bounds_; }

    // At a point whose non-delta lobes are Lambertian and reflect `weight` radiance per unit
    // of irradiance: a level-0 lookup, served by serve_lookups() with the other lookups of the
    // bounce (the octree walks and weights one query after another, the visibility rays of all
    // of them as one batch). It adds weight * E to out[slot] if the cache can interpolate,
    // otherwise queues a record (computed by resolve()). `key` keys its random numbers.
    void queue_lookup(const SurfacePoint& sp, const warp::Frame& frame, const RGB& weight,
                      uint32_t slot, uint64_t key, float path_length, CacheWorkspace& ws) const;
    // Serves the queued lookups in the order they were queued: exactly what interpolating
    // each with its visibility rays traced one by one would have done, in that order.
    // Its time goes to the cache-lookup stage (a lap of `clock`).
    void serve_lookups(CacheWorkspace& ws, std::vector<RGB>& out, RenderStats& stats,
                       StageClock& clock) const;
    // Serves every waiting lookup (level 0's add weight * E to `out`); merges the lookup
    // and visibility counts into `stats`.
    void resolve(CacheWorkspace& ws, std::vector<RGB>& out, RenderStats& stats) const;

  private:
    void resolve_level(uint32_t level, CacheWorkspace& ws, std::vector<RGB>& out,
                       RenderStats& stats) const;
    // Picks this round's record sites among the waiting lookups (spacing = f R_max).
    void pick_sites(CacheLevelWork& work, float f) const;
    void queue_record(CacheLevelWork& work, uint32_t pending) const;
    // Traces the level's record rays and fills its L and dist (deeper lookups may wait).
    void evaluate(uint32_t level, CacheWorkspace& ws, RenderStats& stats) const;
    // Queues a lookup at `level` into b (candidates of caches_[level] and of the level's
    // found records, as they are now).
    void enqueue(uint32_t level, const SurfacePoint& sp, const warp::Frame& frame,
                 const RGB& weight, uint32_t slot, uint64_t key, float path_length,
                 CacheLookupBatch& b, CacheWorkspace& ws) const;
    // Traces b's visibility rays as one batch and interpolates its queries in order: b.served
    // and b.value per query; a query not served joins the level's pending lookups. Counts go
    // to `st` (visibility rays' traversal to ws.trace).
    void serve_batch(uint32_t level, CacheLookupBatch& b, CacheWorkspace& ws,
                     CacheCounters& st) const;
    // The visibility test's segment from sp to r; false when no ray is needed (it passes).
    bool visibility_ray(const SurfacePoint& sp, const IrradianceRecord& r, kern::Ray1& ray) const;
    void queue_pending(const SurfacePoint& sp, const warp::Frame& frame, const RGB& weight,
                       uint32_t slot, uint64_t key, float path_length, CacheLevelWork& work) const;

    const RenderContext ctx_;
    CacheSecondary mode_;
    PhotonRadiance photons_;
    const RadianceAlongRays* path_;
    uint32_t levels_;
    HemisphereStrata strata_;
    CacheParams params_;
    Bounds3 bounds_;
    std::vector<const IrradianceCache*> caches_;
};

}  // namespace foton
