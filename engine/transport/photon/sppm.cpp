#include "sppm.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

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
#include "engine/transport/photon/adaptive_photons.h"
#include "engine/transport/photon/photon_tracer.h"
#include "engine/transport/photon/ppm_error_bound.h"
#include "engine/transport/photon/sppm_visible.h"
#include "engine/transport/run/pass_control.h"
#include "engine/transport/run/stage_graph.h"

namespace foton {

namespace {

// What a visible point's photons brought in one pass: the flux within its radius R, with the
// error bound on also the flux within 2 R (its bias estimate, ppm_error_bound.h), and the count
// within R.
struct PassFlux {
    RGB phi, phi_wide;
    uint32_t count = 0;
};

class ProgressivePhotons {
  public:
    explicit ProgressivePhotons(const Scene& scene) : scene_(scene) {}

    // Gathers this pass's photons within the visible point's radius and updates it; `wide`:
    // also sums the flux within twice the radius. The photons within R and the order they
    // are summed in are the same either way (the kd-tree visits its leaves in one order), so
    // the image does not change with it.
    PassFlux gather(const PhotonMap& photons, float alpha, bool wide, SppmPixel& px) const {
        PassFlux out;
        if (!px.valid) return out;
        std::optional<Material> scratch;
        const Material& m = scene_.material_at(scene_.materials[px.material], px.tex, scratch);
        const BsdfContext ctx{px.front, Transport::Radiance};
        const float r2 = px.radius * px.radius;
        photons.for_each_in_radius(px.p, wide ? 2.f * px.radius : px.radius,
                                   [&](uint32_t i, float d2) {
                                       if (photons.flags(i) & kPhotonDirect)
                                           return;  // direct light came from NEE
                                       const Vec3 w = photons.incident(i);
                                       if (!m.bsdf.side_allowed(w, px.ng)) return;
                                       const RGB f = m.bsdf.f(px.wo, px.frame.to_local(w), ctx);
                                       const RGB add = px.beta * f * photons.power(i);
                                       out.phi_wide += add;
                                       if (d2 >= r2) return;
                                       out.phi += add;
                                       ++out.count;
                                   });
        if (out.count == 0) return out;
        const double n_new = px.n + alpha * out.count;
        const float ratio = float(n_new / (px.n + out.count));
        px.tau = (px.tau + out.phi) * ratio;
        px.radius *= std::sqrt(ratio);
        px.n = n_new;
        return out;
    }

  private:
    const Scene& scene_;
};

// The pass's estimate of a pixel (direct light + density estimate at radius r) and its bias
// estimate, for the error bound: a disc of radius R blurs by R^2 lap(L) / 8 to leading order,
// so E[L(2R)] - E[L(R)] = 3 R^2 lap(L) / 8 = 3 x the bias at R.
void record_pass(const SppmPixel& px, float r, const PassFlux& flux, PpmErrorBound& bound,
                 std::size_t pixel) {
    const float area = float(kPi) * r * r;
    const float inv = area > 0.f ? 1.f / area : 0.f;
    const RGB density = flux.phi * inv, wide = flux.phi_wide * (0.25f * inv);
    bound.record(pixel, px.pass_direct + density, (wide - density) * (1.f / 3.f));
}

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
    // Adaptive photon tracing: chains kept across passes, steered by the pass's visible points.
    std::optional<AdaptivePhotonTracer> adaptive;
    VisiblePointGrid seen;
    if (ps.adaptive_photons)
        adaptive.emplace(tracer, opt.seed, settings.max_depth, ps.unscaled_roulette);
    // The error bound's per-pixel sums, kept when the stopping rule is on.
    std::optional<PpmErrorBound> error;
    if (ps.stop_error > 0.f) error.emplace(npix, ps.stop_confidence);
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
            RGB l = p.direct * (1.f / float(passes));
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
                                  visible_points.trace_row(stochastic ? pass : 0, pass, uint32_t(y),
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
        if (adaptive) {
            seen.build(pixels);
            photons = adaptive->run(s.pass, per_pass, seen, local.local(), opt.cancel, opt.cluster);
        } else {
            photons = tracer.run(s, local.local(), nullptr, nullptr, opt.cluster);
        }
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
                              for (std::size_t i = r.begin(); i != r.end(); ++i) {
                                  if (owner[i] != cluster.rank()) continue;
                                  SppmPixel& px = pixels[i];
                                  const float radius = px.radius;  // this pass's
                                  const PassFlux flux =
                                      pm.gather(photons, ps.alpha, bool(error), px);
                                  px.direct += px.pass_direct;
                                  if (error) record_pass(px, radius, flux, *error, i);
                              }
                          });
        const std::size_t gathered =
            std::size_t(std::count(owner.begin(), owner.end(), int32_t(cluster.rank())));
        RenderStats& st = local.local();
        st.add_wall(Stage::FinalGather, gathered, clock);
        st.samples += gathered;
        return gathered;
    });
    // Adaptive photons follow the pass's visible points (and their radii, updated by the
    // last gather, which precedes this pass's graph).
    if (adaptive) graph.edge(visible, trace);
    graph.edge(trace, balance);
    graph.edge(visible, gather);
    graph.edge(balance, gather);
    // With the stopping rule, the bound decides after each pass (on rank 0, for all ranks).
    double mean_bound = 0.0, mean_value = 0.0;
    bool converged = false;
    do {
        graph.run(arena);
        ++pass;  // the passes the image averages from here on
        task.advance();
        if (error)
            converged = error->converged(pass, ps.stop_error, image(pass).pixels, cluster, owner,
                                         mean_bound, mean_value);
    } while (control.another(
        pass, [&] { return image(pass); }, [&] { return double(pass); }, converged));
    RenderResult result;
    for (const RenderStats& s : local) stats.merge(s);
    stats.wall_seconds = control.elapsed();
    stats.threads = threads;
    stats.passes = pass;
    if (adaptive) {
        const AdaptiveStats& a = adaptive->totals();
        stats.adaptive_uniform = a.uniform;
        stats.adaptive_seen = a.uniform_visible;
        stats.adaptive_mutations = a.mutations;
        stats.adaptive_accepted = a.accepted;
    }
    result.stats = stats;
    result.stats.graph = graph.report();
    result.film = image(pass);
    result.samples_per_pixel.assign(npix, pass);
    if (error) {
        result.stats.error_bound = mean_bound;
        result.stats.error_mean_value = mean_value;
        result.stats.error_confidence = ps.stop_confidence;
        std::vector<RGB> bounds(npix);
        const double t = error->t_factor(pass);
        for (std::size_t i = 0; i < npix; ++i)
            if (owner[i] == cluster.rank()) bounds[i] = error->bound(i, pass, t);
        gather_to_root(cluster, owner, bounds);
        AovLayer layer{"error_bound", {"ErrorBound.R", "ErrorBound.G", "ErrorBound.B"}, {}};
        for (const RGB& b : bounds) layer.values.insert(layer.values.end(), {b.r, b.g, b.b});
        result.aovs.push_back(std::move(layer));
    }
    return result;
}

}  // namespace foton
