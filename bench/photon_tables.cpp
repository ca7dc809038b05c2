// Photon-mapping throughput, measured in one run (medians of --repeats):
//   1. photon tracing: photons emitted and stored per second (global and caustic passes);
//   2. balancing the kd-tree: 1M and 10M photons, 1 thread and all threads;
//   3. radiance-estimate queries per second at k = 50, 100, 200, and Christensen's
//      precomputed-irradiance lookups for comparison;
//   4. final gathering: gather rays per second with and without precomputed irradiance.
// Markdown on stdout.
//
//   build/release/bench/foton_bench_photons [--repeats 3] [--quick]
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "bench_util.h"
#include "engine/accel/intersector.h"
#include "engine/scene/light_set.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/photon/photon_tracer.h"
#include "engine/transport/registry/render.h"

using namespace foton;
using namespace foton::bench;

namespace {

const kern::PointKdTree::ParallelInvoke kTbbInvoke = [](const std::function<void()>& a,
                                                        const std::function<void()>& b) {
    tbb::parallel_invoke(a, b);
};

PhotonMap trace(const Scene& scene, const Intersector& acc, PhotonMapKind kind, uint64_t emitted,
                int threads, double& seconds) {
    const LightSet lights(scene);
    const PhotonTracer tracer(scene, acc, lights, 1);
    PhotonPassSettings s;
    s.kind = kind;
    s.emitted = emitted;
    s.max_depth = render_settings(scene).max_depth;
    RenderStats st;
    PhotonMap map;
    tbb::task_arena arena(threads);
    const auto t0 = Clock::now();
    arena.execute([&] { map = tracer.run(s, st); });
    seconds = seconds_since(t0);
    return map;
}

}  // namespace

int main(int argc, char** argv) {
    int repeats = 3;
    bool quick = false;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--repeats") && i + 1 < argc)
            repeats = std::max(1, std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--quick"))
            quick = true;
        else {
            std::fprintf(stderr, "usage: %s [--repeats N] [--quick]\n", argv[0]);
            return 2;
        }
    }
    const int nproc = std::max(1, int(std::thread::hardware_concurrency()));
    std::printf("foton photon-mapping benchmarks: median of %d runs, %d hardware threads\n\n",
                repeats, nproc);
    const std::vector<int> thread_counts =
        nproc > 1 ? std::vector<int>{1, nproc} : std::vector<int>{1};

    // 1. Tracing.
    std::printf("### Photon tracing (grid accelerator)\n\n");
    std::printf(
        "| scene | map | threads | emitted | stored | emitted/s | stored/s |\n"
        "|---|---|---:|---:|---:|---:|---:|\n");
    for (const char* name : {"cornell-diffuse.xml", "cornell-caustics.xml"}) {
        const Scene s = load_scene(scene_path(name));
        const auto acc = make_intersector(s, AccelType::Grid);
        for (PhotonMapKind kind : {PhotonMapKind::Global, PhotonMapKind::Caustic}) {
            if (kind == PhotonMapKind::Caustic && std::string(name) == "cornell-diffuse.xml")
                continue;
            const uint64_t emitted = quick ? 100000 : 500000;
            for (int t : thread_counts) {
                std::vector<double> times;
                std::size_t stored = 0;
                for (int r = 0; r < repeats; ++r) {
                    double sec;
                    stored = trace(s, *acc, kind, emitted, t, sec).size();
                    times.push_back(sec);
                }
                const double m = median(times);
                std::printf("| %s | %s | %d | %llu | %zu | %.3g | %.3g |\n", name,
                            kind == PhotonMapKind::Global ? "global" : "caustic", t,
                            (unsigned long long)emitted, stored, double(emitted) / m,
                            double(stored) / m);
            }
        }
    }
    std::printf("\n");

    // 2. Balancing, and 3. queries on the larger map.
    const Scene diffuse = load_scene(scene_path("cornell-diffuse.xml"));
    const auto acc = make_intersector(diffuse, AccelType::Grid);
    std::printf("### Balancing the kd-tree (cornell-diffuse.xml photons)\n\n");
    std::printf("| photons | threads | balance [s] | photons/s |\n|---:|---:|---:|---:|\n");
    PhotonMap kept;
    for (uint64_t target : {1000000ull, 10000000ull}) {
        if (quick && target > 1000000ull) continue;
        double sec;
        // A pilot pass tells how many photons are stored per emitted one (about 1.8 here).
        PhotonMap pilot = trace(diffuse, *acc, PhotonMapKind::Global, 20000, nproc, sec);
        const uint64_t emitted = uint64_t(double(target) * 20000.0 / double(pilot.size()));
        PhotonMap map = trace(diffuse, *acc, PhotonMapKind::Global, emitted, nproc, sec);
        for (int t : thread_counts) {
            std::vector<double> times;
            for (int r = 0; r < repeats; ++r) {
                tbb::task_arena arena(t);
                const auto t0 = Clock::now();
                arena.execute([&] { map.build(kTbbInvoke); });
                times.push_back(seconds_since(t0));
            }
            const double m = median(times);
            std::printf("| %zu | %d | %.3f | %.3g |\n", map.size(), t, m, double(map.size()) / m);
        }
        if (target == 1000000ull) kept = std::move(map);
    }
    std::printf("\n");

    // 3. Queries at photon positions (the places estimates are asked for), 1M photons.
    const std::size_t nq = quick ? 20000 : 100000;
    std::vector<Vec3> qp(nq), qn(nq);
    for (std::size_t i = 0; i < nq; ++i) {
        const std::size_t j = (i * 7919u) % kept.size();
        qp[i] = kept.position(j);
        qn[i] = kept.normal(j);
    }
    const float radius = 0.05f * 0.5f * length(diffuse.bounds().diagonal());
    std::printf("### Radiance-estimate queries (%zu photons, %zu queries at photon positions)\n\n",
                kept.size(), nq);
    std::printf("| query | threads | queries/s | mean photons |\n|---|---:|---:|---:|\n");
    auto run_queries = [&](int threads, const std::function<uint32_t(std::size_t)>& q,
                           double& found) {
        std::vector<double> times;
        for (int r = 0; r < repeats; ++r) {
            std::vector<uint64_t> counts(nq);
            tbb::task_arena arena(threads);
            const auto t0 = Clock::now();
            arena.execute([&] {
                tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nq, 256),
                                  [&](const tbb::blocked_range<std::size_t>& b) {
                                      for (std::size_t i = b.begin(); i < b.end(); ++i)
                                          counts[i] = q(i);
                                  });
            });
            times.push_back(seconds_since(t0));
            uint64_t total = 0;
            for (uint64_t c : counts) total += c;
            found = double(total) / double(nq);
        }
        return double(nq) / median(times);
    };
    for (uint32_t k : {50u, 100u, 200u}) {
        EstimateParams p;
        p.k = k;
        p.max_radius = radius;
        for (int t : thread_counts) {
            double found = 0.0;
            const double rate = run_queries(
                t,
                [&](std::size_t i) {
                    uint32_t n = 0;
                    kept.irradiance(qp[i], qn[i], p, &n);
                    return n;
                },
                found);
            std::printf("| irradiance estimate, k = %u, disc | %d | %.3g | %.1f |\n", k, t, rate,
                        found);
        }
    }
    {
        EstimateParams p;
        p.max_radius = radius;
        tbb::task_arena arena(nproc);
        arena.execute([&] {
            kept.precompute_irradiance(
                4, p, [](std::size_t n, const std::function<void(std::size_t, std::size_t)>& body) {
                    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024),
                                      [&](const tbb::blocked_range<std::size_t>& r) {
                                          body(r.begin(), r.end());
                                      });
                });
        });
        for (int t : thread_counts) {
            double found = 0.0;
            const double rate = run_queries(
                t,
                [&](std::size_t i) {
                    RGB e;
                    return kept.lookup_irradiance(qp[i], qn[i], radius, e) ? 1u : 0u;
                },
                found);
            std::printf("| precomputed irradiance lookup (every 4th photon) | %d | %.3g | %.2f |\n",
                        t, rate, found);
        }
    }
    std::printf("\n");

    // 4. Final gathering inside a render.
    std::printf("### Final gathering (cornell-diffuse.xml, 128x128, 1 spp, 64 gather rays)\n\n");
    std::printf(
        "| gather hits read | threads | gather rays per camera-pass second | gather rays per "
        "thread-second | render [s] |\n|---|---:|---:|---:|---:|\n");
    Scene fg = diffuse;
    fg.set_resolution(128, 128);
    RenderSettings fgs = render_settings(fg);
    fgs.integrator = "photon";
    fgs.photon.gather_rays = 64;
    for (uint32_t stride : {4u, 0u}) {
        fgs.photon.irradiance_stride = stride;
        for (int t : thread_counts) {
            std::vector<double> rates, per_thread, walls;
            for (int r = 0; r < repeats; ++r) {
                RenderOptions opt;
                opt.threads = t;
                opt.spp = 1;
                const RenderResult res = render(fg, fgs, *acc, opt);
                const double rays = double(res.stats.stage_items[int(Stage::FinalGather)]);
                const double camera = res.stats.wall_seconds - res.stats.photon_seconds;
                rates.push_back(rays / camera);
                // Tracing the gather rays and the photon estimates at their hits (two stages
                // since the estimates are batched).
                per_thread.push_back(rays / (res.stats.stage_seconds[int(Stage::FinalGather)] +
                                             res.stats.stage_seconds[int(Stage::PhotonEstimate)]));
                walls.push_back(res.stats.wall_seconds);
            }
            std::printf("| %s | %d | %.3g | %.3g | %.3f |\n",
                        stride ? "precomputed irradiance (every 4th photon)" : "full estimate", t,
                        median(rates), median(per_thread), median(walls));
        }
    }
    std::printf("\n");
    return 0;
}
