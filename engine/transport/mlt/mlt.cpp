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
#include "engine/transport/common/film_splats.h"
#include "engine/transport/run/pass_control.h"
#include "engine/transport/run/stage_graph.h"
#include "mlt_paths.h"

namespace foton {

namespace {

constexpr uint32_t kGroupChains = 256;     // the chains one task steps as one batch
constexpr uint32_t kBootstrapBatch = 256;  // bootstrap vectors traced as one batch

// The row's parse leaves MltSettings in `own`; settings made by hand take the defaults.
MltSettings mlt_settings_of(const RenderSettings& settings) {
    const MltSettings* m = std::any_cast<MltSettings>(&settings.own);
    return m ? *m : MltSettings{};
}

// A thread's buffers: its paths' scratch, a batch, and the bootstrap's vectors.
struct ThreadState {
    std::unique_ptr<MltScratch> scratch;
    MltBatch batch;
    std::vector<PrimaryVector> boot;
};

// A contribution added to the image with a weight.
struct ChainSplat {
    uint32_t pixel = 0;
    RGB value;
};

// A Markov chain's current state: what it deposits, and its target value.
struct ChainState {
    std::vector<MltContribution> contrib;
    float f = 0.f;
};

// The chains and the image they splat into: a bootstrap, then steps of every chain at once.
class Chains {
  public:
    Chains(const MltPaths& paths, const MltSettings& ms, uint64_t seed, std::size_t pixels)
        : paths_(paths), ms_(ms), seed_(seed), dims_(paths.dims()), acc_(3 * pixels, 0.0) {}

    // Traces the bootstrap's vectors (in batches over the threads of the calling arena) for
    // their f.
    void bootstrap(tbb::enumerable_thread_specific<ThreadState>& threads) {
        const uint64_t nb = ms_.bootstrap;
        boot_f_.resize(nb);
        const uint64_t batches = (nb + kBootstrapBatch - 1) / kBootstrapBatch;
        tbb::parallel_for(uint64_t(0), batches, [&](uint64_t bi) {
            ThreadState& t = threads.local();
            const uint64_t i0 = bi * kBootstrapBatch;
            const uint64_t n = std::min<uint64_t>(kBootstrapBatch, nb - i0);
            fill_boot(t, i0, n);
            paths_.evaluate(t.batch, *t.scratch);
            std::copy(t.batch.f.begin(), t.batch.f.end(), boot_f_.begin() + std::ptrdiff_t(i0));
        });
    }

    // The chains' starts, drawn from the bootstrap in proportion to f (their deposits traced
    // again); false when no vector carried light (the image is black).
    bool start(tbb::enumerable_thread_specific<ThreadState>& threads) {
        const uint64_t nb = ms_.bootstrap;
        std::vector<double> cdf(nb);
        for (uint64_t i = 0; i < nb; ++i) cdf[i] = sum_f_ += double(boot_f_[i]);
        n_f_ = nb;
        if (!(sum_f_ > 0.0)) return false;
        const uint32_t chains = ms_.chains;
        vectors_.resize(chains);
        state_.resize(chains);
        std::vector<uint64_t> start(chains);
        for (uint32_t c = 0; c < chains; ++c) {
            const double u = double(rng::uniform(seed_, kMltChainStream, c, 0)) * sum_f_;
            const uint64_t j = std::min<uint64_t>(
                nb - 1, uint64_t(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin()));
            start[c] = boot_key(j);
            vectors_[c].reset(dims_, chain_prefix_, start[c], ms_.sigma);
        }
        for_groups(threads, [&](ThreadState& t, uint32_t c0, uint32_t n) {
            MltBatch& b = t.batch;
            b.v.resize(n);
            b.keys.resize(n);
            for (uint32_t j = 0; j < n; ++j) {
                b.v[j] = &vectors_[c0 + j];
                b.keys[j] = start[c0 + j];
            }
            paths_.evaluate(b, *t.scratch);
            for (uint32_t j = 0; j < n; ++j) keep(c0 + j, b, j);
        });
        splats_.resize(chains);
        large_f_.resize(chains);
        return true;
    }

    // Step `t` of every chain: proposals traced in groups over the threads, accepted or not,
    // both states' expected-value splats kept per chain.
    void step(uint64_t t, tbb::enumerable_thread_specific<ThreadState>& threads) {
        for_groups(threads, [&](ThreadState& ts, uint32_t c0, uint32_t n) {
            MltBatch& b = ts.batch;
            b.v.resize(n);
            b.keys.resize(n);
            for (uint32_t j = 0; j < n; ++j) {
                b.keys[j] = rng::hash(seed_, kMltChainStream, c0 + j, t + 1);
                large_f_[c0 + j] = -1.f;
                PrimaryVector& v = vectors_[c0 + j];
                v.step(rng::uniform_from(chain_prefix_, b.keys[j], 0) < ms_.large_step, b.keys[j]);
                b.v[j] = &v;
            }
            paths_.evaluate(b, *ts.scratch);
            for (uint32_t j = 0; j < n; ++j) {
                const uint32_t c = c0 + j;
                ChainState& cur = state_[c];
                const float fy = b.f[j];
                if (vectors_[c].large()) large_f_[c] = fy;
                const float a = cur.f > 0.f ? std::min(1.f, fy / cur.f) : 1.f;
                std::vector<ChainSplat>& out = splats_[c];
                out.clear();
                if (fy > 0.f)
                    for (uint32_t k = b.first[j]; k < b.first[j + 1]; ++k)
                        out.push_back({b.contrib[k].pixel, b.contrib[k].value * (a / fy)});
                if (cur.f > 0.f)
                    for (const MltContribution& m : cur.contrib)
                        out.push_back({m.pixel, m.value * ((1.f - a) / cur.f)});
                if (rng::uniform_from(chain_prefix_, b.keys[j], 1) < a) {
                    keep(c, b, j);
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
        for (const std::vector<ChainSplat>& chain : splats_)
            for (const ChainSplat& sp : chain) {
                double* p = &acc_[3 * std::size_t(sp.pixel)];
                p[0] += sp.value.r;
                p[1] += sp.value.g;
                p[2] += sp.value.b;
            }
        ++steps_;
    }

    // The image so far: b (from the bootstrap and every large step) times the film domain's
    // area in pixels over the mutations (each one sample of the image's integral over
    // [0,1)^2, of which a pixel covers 1 / area) times the splats.
    void image(Film& film, double domain_area) const {
        const double b = n_f_ > 0 ? sum_f_ / double(n_f_) : 0.0;
        const double mutations = double(steps_) * double(ms_.chains);
        const double scale = steps_ > 0 ? b * domain_area / mutations : 0.0;
        for (std::size_t p = 0; p < film.pixels.size(); ++p)
            film.pixels[p] = RGB(float(acc_[3 * p] * scale), float(acc_[3 * p + 1] * scale),
                                 float(acc_[3 * p + 2] * scale));
    }
    uint64_t steps() const { return steps_; }

  private:
    // Bootstrap vector i's key: its numbers are the fresh values of it.
    uint64_t boot_key(uint64_t i) const { return rng::hash(seed_, kMltBootstrapStream, i, 0); }

    void fill_boot(ThreadState& t, uint64_t i0, uint64_t n) const {
        t.boot.resize(n);
        t.batch.v.resize(n);
        t.batch.keys.resize(n);
        for (uint64_t j = 0; j < n; ++j) {
            t.batch.keys[j] = boot_key(i0 + j);
            t.boot[j].reset(dims_, chain_prefix_, t.batch.keys[j], ms_.sigma);
            t.batch.v[j] = &t.boot[j];
        }
    }
    // Chain c's state becomes vector j of the batch.
    void keep(uint32_t c, const MltBatch& b, uint32_t j) {
        ChainState& s = state_[c];
        s.f = b.f[j];
        s.contrib.assign(b.contrib.begin() + b.first[j], b.contrib.begin() + b.first[j + 1]);
    }
    // Calls fn(thread state, first chain, count) for each group of chains, over the threads.
    template <class Fn>
    void for_groups(tbb::enumerable_thread_specific<ThreadState>& threads, Fn&& fn) {
        const uint32_t chains = ms_.chains;
        const uint32_t groups = (chains + kGroupChains - 1) / kGroupChains;
        tbb::parallel_for(uint32_t(0), groups, [&](uint32_t g) {
            const uint32_t c0 = g * kGroupChains;
            fn(threads.local(), c0, std::min(kGroupChains, chains - c0));
        });
    }

    const MltPaths& paths_;
    const MltSettings ms_;
    const uint64_t seed_;
    const uint32_t dims_;
    const uint64_t chain_prefix_ = rng::stream_prefix(seed_, kMltChainStream);
    std::vector<float> boot_f_;
    std::vector<PrimaryVector> vectors_;  // every chain's state
    std::vector<ChainState> state_;
    std::vector<std::vector<ChainSplat>> splats_;  // the step's, per chain
    std::vector<float> large_f_;                   // the step's large steps' f (-1: a small step)
    double sum_f_ = 0.0;                           // f summed over the bootstrap and large steps
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
    static const EnumTable<MltPathKind> kinds{
        {{"path", MltPathKind::Path}, {"bdpt", MltPathKind::Bidirectional}}};
    m.paths = params.choice("mlt_paths", kinds, m.paths);
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
    const std::unique_ptr<MltPaths> paths = ms.paths == MltPathKind::Bidirectional
                                                ? make_bidir_mlt_paths(ctx)
                                                : make_path_mlt_paths(ctx);
    const int w = scene.film.width, h = scene.film.height;
    const std::size_t npix = std::size_t(w) * std::size_t(h);
    const int threads = resolve_threads(opt.threads);
    PinnedArena arena(threads);
    tbb::enumerable_thread_specific<ThreadState> scratch([&] {
        ThreadState s;
        s.scratch = paths->make_scratch();
        return s;
    });
    // The clock (and --time's budget) starts before the bootstrap.
    RenderOptions pass_opt = opt;
    if (pass_opt.max_passes == 0 && !(opt.time_limit > 0.f)) pass_opt.max_passes = 1;
    PassControl control(pass_opt);
    Chains chains(*paths, ms, opt.seed, npix);
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
    bool lit = false;
    arena.execute([&] { lit = chains.start(scratch); });
    // A pass is --spp mutations per pixel; passes as the other integrators count them.
    const uint64_t per_pass =
        (std::max<uint64_t>(1, uint64_t(opt.spp) * npix) + ms.chains - 1) / ms.chains;
    const ProgressTask task = control.task("mlt mutations", per_pass);
    auto image = [&] {
        Film f(w, h);
        chains.image(f, FilmDomain(scene.film).area());
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
    for (const ThreadState& s : scratch) stats.merge(s.scratch->stats);
    stats.samples = ms.bootstrap + chains.steps() * ms.chains;
    stats.passes = passes;
    stats.threads = threads;
    stats.wall_seconds = control.elapsed();
    stats.graph = graph.report();
    result.stats = stats;
    return result;
}

}  // namespace foton
