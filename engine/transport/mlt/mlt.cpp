#include "mlt.h"

#include <algorithm>
#include <any>
#include <cmath>
#include <memory>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "engine/core/error.h"
#include "engine/core/progress.h"
#include "engine/core/rng.h"
#include "engine/core/rng_streams.h"
#include "engine/core/thread_pinning.h"
#include "engine/scene/light_set.h"
#include "engine/transport/common/path_sampler.h"
#include "engine/transport/path/path.h"
#include "engine/transport/run/pass_control.h"
#include "engine/transport/run/stage_graph.h"

namespace foton {

namespace {

constexpr uint32_t kGroupChains = 256;     // the chains one task steps as one batch
constexpr uint32_t kBootstrapBatch = 256;  // bootstrap vectors traced as one batch

// The row's parse leaves MltSettings in `own`; settings made by hand take the defaults.
MltSettings mlt_settings_of(const RenderSettings& settings) {
    const MltSettings* m = std::any_cast<MltSettings>(&settings.own);
    return m ? *m : MltSettings{};
}

// A thread's buffers for tracing a batch of primary vectors.
struct MltScratch {
    std::unique_ptr<IntegratorWorkspace> ws;
    RayBatch rays;
    std::vector<PathSampler> samplers;
    std::vector<uint64_t> keys;
    std::vector<RGB> radiance;
    std::vector<PrimaryVector> boot;   // a bootstrap batch's vectors
    std::vector<PrimaryVector*> v;     // the batch being traced
    std::vector<uint64_t> batch_keys;  // its vectors' keys
    std::vector<RGB> batch_L;          // a step's radiance and pixels
    std::vector<uint32_t> batch_pixel;
    RenderStats stats;
};

// The paths of primary vectors: film position (2), lens (2), then the path tracer's numbers.
class PrimaryPaths {
  public:
    PrimaryPaths(const RenderContext& ctx, uint32_t dims)
        : ctx_(ctx), path_(ctx, VertexRules::path(ctx.settings)), dims_(dims) {}
    uint32_t dims() const { return dims_; }
    std::unique_ptr<IntegratorWorkspace> make_workspace() const { return path_.make_workspace(); }

    // The radiance and pixel of the n vectors s.v (their film position and lens, then the
    // path's numbers, read as the path asks for them); s.batch_keys key numbers past a vector's
    // end.
    void evaluate(std::size_t n, MltScratch& s, RGB* L, uint32_t* pixel) const {
        const FilmSettings& film = ctx_.scene.film;
        const std::vector<PrimaryVector*>& v = s.v;
        s.rays.clear();
        s.samplers.resize(n);
        s.keys.assign(s.batch_keys.begin(), s.batch_keys.begin() + std::ptrdiff_t(n));
        for (std::size_t i = 0; i < n; ++i) {
            const float fx = v[i]->get(0) * float(film.width),
                        fy = v[i]->get(1) * float(film.height);
            const int px = std::min(int(fx), film.width - 1),
                      py = std::min(int(fy), film.height - 1);
            pixel[i] = uint32_t(py) * uint32_t(film.width) + uint32_t(px);
            Vec3 o, d;
            ctx_.scene.camera.generate(float(film.x0) + fx, float(film.y0) + fy,
                                       {v[i]->get(2), v[i]->get(3)}, o, d);
            s.rays.push(o, d, 0.f, kInfinity, uint32_t(i));
            s.samplers[i] = PathSampler::primary(v[i], 4, s.keys[i], ctx_.seed);
        }
        path_.trace_camera_paths(s.rays, s.samplers, s.keys, *s.ws, s.radiance, s.stats);
        for (std::size_t i = 0; i < n; ++i)
            L[i] = s.radiance[i].is_finite() ? s.radiance[i] : RGB{};
    }

  private:
    const RenderContext& ctx_;
    const PathIntegrator path_;
    uint32_t dims_;
};

// The target function: the luminance of a path's radiance (0 for none or negative).
float mlt_target(const RGB& L) {
    return std::max(0.f, L.luminance());
}

// A Markov chain's current state.
struct ChainState {
    RGB L;
    float f = 0.f;
    uint32_t pixel = 0;
};

// A state's radiance added to its pixel with a weight.
struct ChainSplat {
    uint32_t pixel = 0;
    RGB value;
};

// The chains and the image they splat into: a bootstrap, then steps of every chain at once.
class Chains {
  public:
    Chains(const PrimaryPaths& paths, const MltSettings& ms, uint64_t seed, std::size_t pixels)
        : paths_(paths), ms_(ms), seed_(seed), dims_(paths.dims()), acc_(3 * pixels, 0.0) {}

    // Traces the bootstrap's vectors (in batches over the threads of the calling arena).
    void bootstrap(tbb::enumerable_thread_specific<MltScratch>& scratch) {
        const uint64_t nb = ms_.bootstrap;
        boot_L_.resize(nb);
        boot_pixel_.resize(nb);
        const uint64_t batches = (nb + kBootstrapBatch - 1) / kBootstrapBatch;
        tbb::parallel_for(uint64_t(0), batches, [&](uint64_t bi) {
            MltScratch& s = scratch.local();
            const uint64_t i0 = bi * kBootstrapBatch;
            const uint64_t n = std::min<uint64_t>(kBootstrapBatch, nb - i0);
            s.boot.resize(n);
            s.v.resize(n);
            s.batch_keys.resize(n);
            for (uint64_t j = 0; j < n; ++j) {
                s.batch_keys[j] = boot_key(i0 + j);
                s.boot[j].reset(dims_, chain_prefix_, s.batch_keys[j], ms_.sigma);
                s.v[j] = &s.boot[j];
            }
            paths_.evaluate(n, s, &boot_L_[i0], &boot_pixel_[i0]);
        });
    }

    // The chains' starts, drawn from the bootstrap in proportion to f; false when no vector
    // carried light (the image is black).
    bool start() {
        const uint64_t nb = ms_.bootstrap;
        std::vector<double> cdf(nb);
        for (uint64_t i = 0; i < nb; ++i) cdf[i] = sum_f_ += double(mlt_target(boot_L_[i]));
        n_f_ = nb;
        if (!(sum_f_ > 0.0)) return false;
        const uint32_t chains = ms_.chains;
        vectors_.resize(chains);
        state_.resize(chains);
        for (uint32_t c = 0; c < chains; ++c) {
            const double u = double(rng::uniform(seed_, kMltChainStream, c, 0)) * sum_f_;
            const uint64_t j = std::min<uint64_t>(
                nb - 1, uint64_t(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin()));
            vectors_[c].reset(dims_, chain_prefix_, boot_key(j), ms_.sigma);
            state_[c] = {boot_L_[j], mlt_target(boot_L_[j]), boot_pixel_[j]};
        }
        splats_.resize(2 * std::size_t(chains));
        large_f_.resize(chains);
        return true;
    }

    // Step `t` of every chain: proposals traced in groups over the threads, accepted or not.
    void step(uint64_t t, tbb::enumerable_thread_specific<MltScratch>& scratch) {
        const uint32_t chains = ms_.chains;
        const uint32_t groups = (chains + kGroupChains - 1) / kGroupChains;
        tbb::parallel_for(uint32_t(0), groups, [&](uint32_t g) {
            MltScratch& s = scratch.local();
            const uint32_t c0 = g * kGroupChains, n = std::min(kGroupChains, chains - c0);
            s.v.resize(n);
            std::vector<uint64_t>& keys = s.batch_keys;
            keys.resize(n);
            for (uint32_t j = 0; j < n; ++j) {
                keys[j] = rng::hash(seed_, kMltChainStream, c0 + j, t + 1);
                large_f_[c0 + j] = -1.f;
                PrimaryVector& v = vectors_[c0 + j];
                v.step(rng::uniform_from(chain_prefix_, keys[j], 0) < ms_.large_step, keys[j]);
                s.v[j] = &v;
            }
            std::vector<RGB>& L = s.batch_L;
            std::vector<uint32_t>& pixel = s.batch_pixel;
            L.resize(n);
            pixel.resize(n);
            paths_.evaluate(n, s, L.data(), pixel.data());
            // Acceptance, and both states' expected-value splats.
            for (uint32_t j = 0; j < n; ++j) {
                const uint32_t c = c0 + j;
                ChainState& cur = state_[c];
                const float fy = mlt_target(L[j]);
                if (vectors_[c].large()) large_f_[c] = fy;
                const float a = cur.f > 0.f ? std::min(1.f, fy / cur.f) : 1.f;
                splats_[2 * c] = {pixel[j], fy > 0.f ? L[j] * (a / fy) : RGB{}};
                splats_[2 * c + 1] = {cur.pixel, cur.f > 0.f ? cur.L * ((1.f - a) / cur.f) : RGB{}};
                if (rng::uniform_from(chain_prefix_, keys[j], 1) < a) {
                    cur = {L[j], fy, pixel[j]};
                    vectors_[c].accept();
                } else {
                    vectors_[c].reject();
                }
            }
        });
    }

    // The step's splats and large steps, in chain order: the image does not depend on which
    // thread stepped which group.
    void splat() {
        for (const float f : large_f_)
            if (f >= 0.f) {
                sum_f_ += double(f);
                ++n_f_;
            }
        for (const ChainSplat& sp : splats_) {
            double* p = &acc_[3 * std::size_t(sp.pixel)];
            p[0] += sp.value.r;
            p[1] += sp.value.g;
            p[2] += sp.value.b;
        }
        ++steps_;
    }

    // The image so far: b (from the bootstrap and every large step) times the pixels over the
    // mutations (each one sample of the image's integral over [0,1)^2, of which a pixel covers
    // 1 / pixels) times the splats.
    void image(Film& film) const {
        const double b = n_f_ > 0 ? sum_f_ / double(n_f_) : 0.0;
        const double mutations = double(steps_) * double(ms_.chains);
        const double scale = steps_ > 0 ? b * double(film.pixels.size()) / mutations : 0.0;
        for (std::size_t p = 0; p < film.pixels.size(); ++p)
            film.pixels[p] = RGB(float(acc_[3 * p] * scale), float(acc_[3 * p + 1] * scale),
                                 float(acc_[3 * p + 2] * scale));
    }
    uint64_t steps() const { return steps_; }

  private:
    // Bootstrap vector i's key: its numbers are the fresh values of it.
    uint64_t boot_key(uint64_t i) const { return rng::hash(seed_, kMltBootstrapStream, i, 0); }

    const PrimaryPaths& paths_;
    const MltSettings ms_;
    const uint64_t seed_;
    const uint32_t dims_;
    const uint64_t chain_prefix_ = rng::stream_prefix(seed_, kMltChainStream);
    std::vector<RGB> boot_L_;
    std::vector<uint32_t> boot_pixel_;
    std::vector<PrimaryVector> vectors_;  // every chain's state
    std::vector<ChainState> state_;
    std::vector<ChainSplat> splats_;  // the step's: two per chain
    std::vector<float> large_f_;      // the step's large steps' f (-1: a small step)
    double sum_f_ = 0.0;              // f summed over the bootstrap and the large steps
    uint64_t n_f_ = 0;
    std::vector<double> acc_;  // the splats, per pixel and channel
    uint64_t steps_ = 0;
};

}  // namespace

void parse_mlt(const ParamSet& params, RenderSettings& settings) {
    MltSettings m;
    m.chains = uint32_t(params.integer("mlt_chains", m.chains, 1, 1u << 20));
    m.bootstrap = params.integer("mlt_bootstrap", m.bootstrap, 1, 1ull << 32);
    m.large_step = params.real("large_step", m.large_step, 0.f, 1.f);
    m.sigma = params.real("mlt_sigma", m.sigma, 1e-6f, 1.f);
    settings.own = m;
}

RenderResult render_mlt(const Scene& scene, const RenderSettings& settings,
                        const Intersector& accel, const RenderOptions& opt) {
    if (cluster_or_solo(opt.cluster).distributed())
        throw InputError(scene.source, 0,
                         "type=\"mlt\" runs in one process (its chains' splats are summed in one "
                         "order); run it without mpirun");
    const MltSettings ms = mlt_settings_of(settings);
    const LightSet lights(scene, settings.light_selection, settings.projection_maps);
    const RenderContext ctx{scene, settings, accel, lights, opt.seed};
    const PrimaryPaths paths(ctx, 4 + (settings.max_depth + 1) * kPathDimsPerBounce);
    const int w = scene.film.width, h = scene.film.height;
    const std::size_t npix = std::size_t(w) * std::size_t(h);
    const int threads = resolve_threads(opt.threads);
    PinnedArena arena(threads);
    tbb::enumerable_thread_specific<MltScratch> scratch([&] {
        MltScratch s;
        s.ws = paths.make_workspace();
        return s;
    });
    // The clock (and --time's budget) starts before the bootstrap.
    RenderOptions pass_opt = opt;
    if (pass_opt.max_passes == 0 && !(opt.time_limit > 0.f)) pass_opt.max_passes = 1;
    PassControl control(pass_opt);
    Chains chains(paths, ms, opt.seed, npix);
    // The graph: the bootstrap once, then per step the proposals and their splats.
    StageGraph graph;
    graph.set_progress(opt.progress);
    uint64_t t = 0;
    const uint32_t boot = graph.add("bootstrap", [&]() -> uint64_t {
        chains.bootstrap(scratch);
        return ms.bootstrap;
    });
    const uint32_t mutate = graph.add("mutate", [&]() -> uint64_t {
        chains.step(t, scratch);
        return ms.chains;
    });
    const uint32_t splat = graph.add("splat", [&]() -> uint64_t {
        chains.splat();
        return 2 * uint64_t(ms.chains);
    });
    graph.edge(boot, mutate);
    graph.edge(mutate, splat);
    graph.run(arena, {boot});
    const bool lit = chains.start();
    // A pass is --spp mutations per pixel; passes as the other integrators count them.
    const uint64_t per_pass =
        (std::max<uint64_t>(1, uint64_t(opt.spp) * npix) + ms.chains - 1) / ms.chains;
    const ProgressTask task = control.task("mlt mutations", per_pass);
    auto image = [&] {
        Film f(w, h);
        chains.image(f);
        return f;
    };
    const uint32_t passes = control.run(
        [&](uint32_t) {
            for (uint64_t k = 0; k < per_pass && lit; ++k) {
                if (opt.cancel && opt.cancel->load(std::memory_order_relaxed)) break;
                graph.run(arena, {mutate, splat});
                ++t;
                task.advance();
            }
        },
        image, [&] { return double(chains.steps()) * double(ms.chains) / double(npix); });
    RenderResult result;
    result.film = image();
    result.samples_per_pixel.assign(npix, uint32_t(chains.steps() * ms.chains / npix));
    RenderStats stats;
    for (const MltScratch& s : scratch) stats.merge(s.stats);
    stats.samples = ms.bootstrap + chains.steps() * ms.chains;
    stats.passes = passes;
    stats.threads = threads;
    stats.wall_seconds = control.elapsed();
    stats.graph = graph.report();
    result.stats = stats;
    return result;
}

}  // namespace foton
