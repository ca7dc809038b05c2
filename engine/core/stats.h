#pragma once
// Render statistics: ray counts, intersection work and per-stage time. Each worker thread
// fills its own RenderStats; they are merged once at the end, so counting costs no atomics.
#include <chrono>
#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <utility>
#include <vector>

namespace foton {

// Camera wavefront stages, then the photon mapper's (a stage that did nothing is not printed).
enum class Stage {
    Generate,
    Intersect,
    Shade,
    Occlusion,
    Accumulate,
    PhotonEmit,
    PhotonIntersect,
    PhotonTrace,
    PhotonStore,
    Balance,
    Precompute,
    GuideBins,      // photon-guided paths: binning the guide's photons into histograms
    LightVertices,  // bdpt/bpm/vcm: the light subpaths' vertices gathered, the merge grid built
    FinalGather,
    PhotonEstimate,
    CacheRecords,
    CacheLookup,
    kCount
};
inline constexpr int kNumStages = int(Stage::kCount);
const char* stage_name(Stage s);

// Work counted by the intersectors.
struct TraceCounters {
    uint64_t triangle_tests = 0;  // ray/triangle tests (a SIMD block counts its W lanes)
    uint64_t sphere_tests = 0;
    uint64_t curve_tests = 0;      // ray/curve segment tests (CurveIntersector)
    uint64_t shape_tests = 0;      // ray/analytic shape or CSG tree tests (ShapeIntersector)
    uint64_t cells = 0;            // grid cells visited (grid backend only)
    uint64_t bvh_nodes = 0;        // wide BVH nodes visited, N box tests each (bvh backend only)
    uint64_t instance_visits = 0;  // rays taken into an instance's space (its BLAS traced)
    void merge(const TraceCounters& o) {
        instance_visits += o.instance_visits;
        triangle_tests += o.triangle_tests;
        sphere_tests += o.sphere_tests;
        curve_tests += o.curve_tests;
        shape_tests += o.shape_tests;
        cells += o.cells;
        bvh_nodes += o.bvh_nodes;
    }
};

// Irradiance-cache lookups.
struct CacheCounters {
    uint64_t lookups = 0, interpolated = 0;
    uint64_t candidates = 0;  // records tested by weight
    uint64_t used = 0;        // records that entered an interpolation
    uint64_t visibility_tests = 0, visibility_rejections = 0;
    void merge(const CacheCounters& o) {
        lookups += o.lookups;
        interpolated += o.interpolated;
        candidates += o.candidates;
        used += o.used;
        visibility_tests += o.visibility_tests;
        visibility_rejections += o.visibility_rejections;
    }
};

class StageClock {
  public:
    StageClock() : start_(std::chrono::steady_clock::now()) {}
    // Seconds since construction or the last lap.
    double lap() {
        const auto now = std::chrono::steady_clock::now();
        const double s = std::chrono::duration<double>(now - start_).count();
        start_ = now;
        return s;
    }

  private:
    std::chrono::steady_clock::time_point start_;
};

// The render's stage graph as it ran (transport/run/stage_graph.h): its nodes, the time their
// bodies ran summed over all runs, the items they processed, and the dependencies between them. A
// node that runs once per pass parallelises inside, so its time is wall time, unless it
// timed its parallel chunks (the passes that run side by side do): then, like a tile node's
// (one run per tile, on many threads at once), its time is thread time.
struct GraphStats {
    struct Node {
        std::string name;
        double busy_seconds = 0.0;
        uint64_t items = 0;
        uint64_t runs = 0;  // times the node ran (once per pass, or per tile)
        // busy_seconds is thread time (a tile node, or a pass node that timed its chunks:
        // summed over the threads running it) rather than wall time (a node that runs once
        // per pass, parallel inside).
        bool thread_time = false;
    };
    std::vector<Node> nodes;
    std::vector<std::pair<uint32_t, uint32_t>> edges;  // from, to (indices into nodes)
};

struct RenderStats {
    uint64_t camera_rays = 0, secondary_rays = 0, shadow_rays = 0;
    uint64_t samples = 0;  // pixel samples (camera integrators) or light paths (light tracer)
    uint32_t passes = 0;   // progressive passes completed
    uint64_t photons_global = 0, photons_caustic = 0;  // stored (photon mapping)
    double photon_seconds = 0.0;     // wall time of the photon passes and the balancing
    uint64_t shadow_rays_saved = 0;  // visibility decided by shadow photons instead
    // Adaptive photon tracing (sppm, ppm): uniform proposals and those a visible point saw;
    // mutations and those accepted.
    uint64_t adaptive_uniform = 0, adaptive_seen = 0, adaptive_mutations = 0, adaptive_accepted = 0;
    // Irradiance cache: records computed (by fill passes and, unstored, by the final pass),
    // records kept (set once, not merged), and the lookups of the final pass.
    uint64_t cache_records = 0, cache_stored = 0;
    double cache_fill_seconds = 0.0;  // wall time of the fill passes (set once)
    CacheCounters cache;
    TraceCounters trace;
    double stage_seconds[kNumStages] = {};  // summed over threads (wall, see stage_wall)
    uint64_t stage_items[kNumStages] = {};
    // Stages timed by one clock around work that ran on many threads (a balance, a
    // precomputation, SPPM's passes): their seconds are wall time, not thread time.
    bool stage_wall[kNumStages] = {};
    // ppm / sppm with an error bound (ppm_error_bound.h), set once on rank 0: the mean of the
    // pixels' luminance error bounds after the last pass and the image's mean luminance, at
    // `error_confidence` (0: no bound was kept).
    double error_bound = 0.0, error_mean_value = 0.0;
    float error_confidence = 0.f;
    double wall_seconds = 0.0;
    double build_seconds = 0.0;
    GraphStats graph;  // set once by the render's driver, not merged
    int threads = 1;

    // The one way a stage reports: `items` processed since the clock's last lap.
    void add(Stage s, uint64_t items, StageClock& clock) {
        stage_items[int(s)] += items;
        stage_seconds[int(s)] += clock.lap();
    }
    // The same for a clock that ran around parallel work: wall time, labelled so.
    void add_wall(Stage s, uint64_t items, StageClock& clock) {
        add(s, items, clock);
        stage_wall[int(s)] = true;
    }
    void merge(const RenderStats& o);
    // Calls f(a.x, b.x) for every counter merge() sums: one list for merging and for
    // moving a rank's counters to rank 0 (stats_wire.h).
    template <class A, class B, class F>
    static void for_each_summed(A& a, B& b, F&& f) {
        f(a.camera_rays, b.camera_rays);
        f(a.secondary_rays, b.secondary_rays);
        f(a.shadow_rays, b.shadow_rays);
        f(a.samples, b.samples);
        f(a.shadow_rays_saved, b.shadow_rays_saved);
        f(a.cache_records, b.cache_records);
        f(a.adaptive_uniform, b.adaptive_uniform);
        f(a.adaptive_seen, b.adaptive_seen);
        f(a.adaptive_mutations, b.adaptive_mutations);
        f(a.adaptive_accepted, b.adaptive_accepted);
        f(a.cache.lookups, b.cache.lookups);
        f(a.cache.interpolated, b.cache.interpolated);
        f(a.cache.candidates, b.cache.candidates);
        f(a.cache.used, b.cache.used);
        f(a.cache.visibility_tests, b.cache.visibility_tests);
        f(a.cache.visibility_rejections, b.cache.visibility_rejections);
        f(a.trace.triangle_tests, b.trace.triangle_tests);
        f(a.trace.sphere_tests, b.trace.sphere_tests);
        f(a.trace.curve_tests, b.trace.curve_tests);
        f(a.trace.shape_tests, b.trace.shape_tests);
        f(a.trace.cells, b.trace.cells);
        f(a.trace.bvh_nodes, b.trace.bvh_nodes);
        f(a.trace.instance_visits, b.trace.instance_visits);
        for (int i = 0; i < kNumStages; ++i) {
            f(a.stage_seconds[i], b.stage_seconds[i]);
            f(a.stage_items[i], b.stage_items[i]);
        }
    }
    uint64_t total_rays() const { return camera_rays + secondary_rays + shadow_rays; }
    std::string table() const;  // human-readable, for --stats
    // For --stats-json: the run's own fields (`run`, an object) first, then the counters, the
    // stage table and the graph. json() is its text.
    nlohmann::ordered_json json_object(const nlohmann::ordered_json& run) const;
    std::string json() const;
    std::string json(const nlohmann::ordered_json& run) const;
};

}  // namespace foton
