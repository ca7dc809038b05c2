#include "sppm.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "engine/core/error.h"
#include "engine/core/thread_pinning.h"
#include "engine/core/warp.h"
#include "engine/film/pixel_owners.h"
#include "engine/scene/light_set.h"
#include "engine/transport/common/camera_integrator.h"
#include "engine/transport/common/surface.h"
#include "engine/transport/photon/photon_tracer.h"
#include "engine/transport/photon/sppm_visible.h"
#include "engine/transport/run/pass_control.h"
#include "engine/transport/run/stage_graph.h"

namespace foton {

namespace {

class ProgressivePhotons {
  public:
    explicit ProgressivePhotons(const Scene& scene) : scene_(scene) {}

    // Gathers this pass's photons within the visible point's radius and updates it.
    void gather(const PhotonMap& photons, float alpha, SppmPixel& px) const {
        if (!px.valid) return;
        std::optional<Material> scratch;
        const Material& m = scene_.material_at(scene_.materials[px.material], px.uv, scratch);
        const BsdfContext ctx{px.front, Transport::Radiance};
        RGB phi;
        uint32_t count = 0;
        photons.for_each_in_radius(px.p, px.radius, [&](uint32_t i, float) {
            if (photons.flags(i) & kPhotonDirect) return;  // direct light came from NEE
            const Vec3 w = photons.incident(i);
            if (!m.bsdf.side_allowed(w, px.ng)) return;
            const RGB f = m.bsdf.f(px.wo, px.frame.to_local(w), ctx);
            phi += px.beta * f * photons.power(i);
            ++count;
        });
        if (count == 0) return;
        const double n_new = px.n + alpha * count;
        const float ratio = float(n_new / (px.n + count));
        px.tau = (px.tau + phi) * ratio;
        px.radius *= std::sqrt(ratio);
        px.n = n_new;
    }

  private:
    const Scene& scene_;
};

}  // namespace

RenderResult render_progressive_photons(const Scene& scene, const RenderSettings& settings,
                                        const Intersector& accel, const RenderOptions& opt,
                                        bool stochastic) {
    const PhotonSettings& ps = settings.photon;
    const LightSet lights(scene, settings.light_selection, settings.projection_maps);
    if (lights.empty()) throw InputError(scene.source, 0, "photon mapping needs a light");
    const int w = scene.film.width, h = scene.film.height;
    const std::size_t npix = std::size_t(w) * std::size_t(h);
    const float radius0 = ps.initial_radius > 0.f
                              ? ps.initial_radius
                              : 0.01f * 0.5f * length(scene.bounds().diagonal());
    // A pass's photons default to the full image's pixel count, crop window or not.
    const uint64_t per_pass =
        ps.photons_per_pass > 0 ? ps.photons_per_pass : scene.film.full_pixels();
    std::vector<SppmPixel> pixels(npix);
    for (SppmPixel& p : pixels) p.radius = radius0;
    const ProgressivePhotons pm(scene);
    const VisiblePoints visible_points(RenderContext{scene, settings, accel, lights, opt.seed});
    tbb::enumerable_thread_specific<VisibleRowWork> row_work;
    const PhotonTracer tracer(scene, accel, lights, opt.seed);
    const int threads = resolve_threads(opt.threads);
    PinnedArena arena(threads);
    RenderStats stats;
    tbb::enumerable_thread_specific<RenderStats> local;
    // Across MPI ranks the image rows are dealt out in turn; every rank traces a share of
    // each pass's photons and gathers from the whole map (photon_tracer.h) for its rows.
    const Cluster& cluster = cluster_or_solo(opt.cluster);
    const PixelOwners owner = owners_by_row(w, h, cluster.size());
    const std::vector<uint64_t> my_rows = dealt_in_turn(uint64_t(h), cluster);
    auto image = [&](uint32_t passes) {
        Film f(w, h);
        // A pass's photons carry its light's flux divided by the photons of the pass, so tau
        // is averaged over passes.
        for (std::size_t i = 0; i < npix; ++i) {
            const SppmPixel& p = pixels[i];
            // PPM's visible points, and so their direct light, come from the first pass only.
            RGB l = p.direct * (1.f / float(stochastic ? passes : 1));
            if (p.radius > 0.f)
                l += p.tau * float(1.0 / (double(passes) * kPi * double(p.radius) * p.radius));
            f.pixels[i] = l;
        }
        gather_to_root(cluster, owner, f.pixels);
        return f;
    };
    // Passes: max_passes, else opt.spp of them, or as many as fit in the time limit.
    RenderOptions pass_opt = opt;
    if (pass_opt.max_passes == 0 && !(opt.time_limit > 0.f))
        pass_opt.max_passes = std::max<uint32_t>(1, opt.spp);
    PassControl control(pass_opt);
    const ProgressTask task = control.task(stochastic ? "sppm passes" : "ppm passes", 1);
    uint32_t pass = 0;
    // A pass as a graph: the visible points (SPPM: every pass; PPM: the first) and the
    // pass's photons are independent and run side by side; the photons are balanced; then
    // every visible point gathers.
    StageGraph graph;
    graph.set_progress(opt.progress);
    PhotonMap photons;
    const uint32_t visible = graph.add("visible-points", [&]() -> uint64_t {
        if (!stochastic && pass > 0) return 0;
        StageClock clock;
        const std::size_t rows = my_rows.size();
        BusyTime* const busy = ThreadClock::for_chunks();
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rows),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              const ThreadClock clock(busy);
                              RenderStats& st = local.local();
                              VisibleRowWork& work = row_work.local();
                              for (std::size_t i = r.begin(); i != r.end(); ++i) {
                                  if (opt.cancel && opt.cancel->load(std::memory_order_relaxed))
                                      return;  // a cancelled pass traces no further row
                                  const std::size_t y = my_rows[i];
                                  visible_points.trace_row(pass, uint32_t(y),
                                                           &pixels[y * std::size_t(w)], work, st);
                              }
                          });
        local.local().add_wall(Stage::Shade, rows * std::size_t(w), clock);
        return rows * std::size_t(w);
    });
    const uint32_t trace = graph.add("photons", [&]() -> uint64_t {
        PhotonPassSettings s;
        s.kind = PhotonMapKind::Global;
        s.emitted = per_pass;
        s.max_depth = settings.max_depth;
        s.unscaled_roulette = ps.unscaled_roulette;
        s.pass = 1000 + pass;
        s.cancel = opt.cancel;
        photons = tracer.run(s, local.local(), nullptr, nullptr, opt.cluster);
        if (settings.photon.compact_power) photons.compact_power();
        return per_pass;
    });
    const uint32_t balance = graph.add("balance", [&]() -> uint64_t {
        StageClock clock;
        photons.build(timed_parallel_invoke(ThreadClock::for_chunks()));
        local.local().add_wall(Stage::Balance, photons.size(), clock);
        return photons.size();
    });
    const uint32_t gather = graph.add("gather", [&]() -> uint64_t {
        StageClock clock;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, npix, 256),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t i = r.begin(); i != r.end(); ++i)
                                  if (owner[i] == cluster.rank())
                                      pm.gather(photons, ps.alpha, pixels[i]);
                          });
        const std::size_t gathered =
            std::size_t(std::count(owner.begin(), owner.end(), int32_t(cluster.rank())));
        RenderStats& st = local.local();
        st.add_wall(Stage::FinalGather, gathered, clock);
        st.samples += gathered;
        return gathered;
    });
    graph.edge(trace, balance);
    graph.edge(visible, gather);
    graph.edge(balance, gather);
    control.run(
        [&](uint32_t k) {
            pass = k;
            graph.run(arena);
            pass = k + 1;  // the passes the image averages from here on
            task.advance();
        },
        [&] { return image(pass); }, [&] { return double(pass); });
    RenderResult result;
    for (const RenderStats& s : local) stats.merge(s);
    stats.wall_seconds = control.elapsed();
    stats.threads = threads;
    stats.passes = pass;
    result.stats = stats;
    result.stats.graph = graph.report();
    result.film = image(pass);
    result.samples_per_pixel.assign(npix, pass);
    return result;
}

}  // namespace foton
