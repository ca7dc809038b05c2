// Reproduces the first thesis' measurements (chapter 11) as ratios measured in one run:
//   1. brute force vs grid on the ~4K-triangle scene, 1 thread, 1 sample per pixel
//      (the thesis: 3,936-triangle monkey, 5:15 vs 0:04);
//   2. grid vs Embree on the bunny and the dragon, 1 thread, 1 spp;
//   3. render time for 1..N threads and the speed-up (the thesis: 4 spp, 1024 x 800);
//   4. every integrator on the dragon with bvh, grid and embree inside the renderer: render
//      time, rays/s and the share of the stage time spent tracing (intersect + occlusion).
// Every time is the median of --repeats renders; the tables are markdown on stdout.
//
//   build/release/bench/foton_bench_render [--repeats 5] [--quick]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "bench_util.h"
#include "engine/accel/intersector.h"
#include "engine/core/stats.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/render.h"

using namespace foton;
using bench::median;
using bench::scene_path;

namespace {

struct Timing {
    double build = 0.0;   // median accelerator build, s
    double render = 0.0;  // median render, s
    double rays_per_s = 0.0;
    double trace_share = 0.0;  // (intersect + occlusion) / all stages, of the median render
};

Timing measure(const Scene& scene, const RenderSettings& settings, AccelType accel, int threads,
               uint32_t spp, int repeats) {
    std::vector<double> builds, renders, rates, shares;
    for (int r = 0; r < repeats; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        const auto acc = make_intersector(scene, accel, threads);
        builds.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        RenderOptions opt;
        opt.threads = threads;
        opt.spp = spp;
        const RenderResult res = render(scene, settings, *acc, opt);
        renders.push_back(res.stats.wall_seconds);
        rates.push_back(double(res.stats.total_rays()) / res.stats.wall_seconds);
        double all = 0.0;
        for (double x : res.stats.stage_seconds) all += x;
        shares.push_back(all > 0.0 ? (res.stats.stage_seconds[int(Stage::Intersect)] +
                                      res.stats.stage_seconds[int(Stage::Occlusion)]) /
                                         all
                                   : 0.0);
    }
    return {median(builds), median(renders), median(rates), median(shares)};
}

}  // namespace

int main(int argc, char** argv) {
    int repeats = 5;
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
    const int nproc = int(std::thread::hardware_concurrency());
    std::printf("foton render benchmarks: median of %d runs, %d hardware threads\n\n", repeats,
                nproc);

    {
        const Scene s = load_scene(scene_path("torus-knot.xml"));
        std::printf(
            "### Brute force vs grid (torus-knot.xml, %zu triangles, %dx%d, 1 spp, 1 thread)\n\n",
            s.num_triangles(), s.film.width, s.film.height);
        std::printf(
            "| accelerator | build [s] | render [s] | rays/s | brute / this "
            "|\n|---|---:|---:|---:|---:|\n");
        // The scalar brute force takes seconds per run: fewer repeats, it is not noisy.
        const Timing brute = measure(s, render_settings(s), AccelType::Brute, 1, 1,
                                     quick ? 1 : std::min(repeats, 3));
        for (AccelType a :
             {AccelType::Brute, AccelType::BruteSimd, AccelType::Grid, AccelType::Octree,
              AccelType::KdTree, AccelType::Bvh, AccelType::Embree}) {
            const Timing t =
                a == AccelType::Brute ? brute : measure(s, render_settings(s), a, 1, 1, repeats);
            std::printf("| %s | %.4f | %.4f | %.3g | %.1fx |\n", accel_name(a), t.build, t.render,
                        t.rays_per_s, brute.render / t.render);
        }
        std::printf("\n");
    }
    {
        std::printf("### Grid vs Embree (1 spp, 1 thread)\n\n");
        std::printf(
            "| scene | triangles | grid build [s] | embree build [s] | grid render [s] | embree "
            "render [s] | grid rays/s | embree rays/s | grid / embree speed |\n");
        std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
        for (const char* name : {"bunny.xml", "dragon.xml"}) {
            if (quick && std::string(name) == "dragon.xml") continue;
            const Scene s = load_scene(scene_path(name));
            const Timing g = measure(s, render_settings(s), AccelType::Grid, 1, 1, repeats);
            const Timing e = measure(s, render_settings(s), AccelType::Embree, 1, 1, repeats);
            std::printf("| %s | %zu | %.3f | %.3f | %.4f | %.4f | %.3g | %.3g | %.2fx |\n", name,
                        s.num_triangles(), g.build, e.build, g.render, e.render, g.rays_per_s,
                        e.rays_per_s, e.render / g.render);
        }
        std::printf("\n");
    }
    {
        const Scene s = load_scene(scene_path("bunny.xml"));
        std::printf("### Thread scaling (bunny.xml, %dx%d, 4 spp, grid)\n\n", s.film.width,
                    s.film.height);
        std::printf("| threads | render [s] | speed-up | efficiency |\n|---:|---:|---:|---:|\n");
        double t1 = 0.0;
        for (int t = 1; t <= std::max(nproc, 1); ++t) {
            const Timing r = measure(s, render_settings(s), AccelType::Grid, t, 4, repeats);
            if (t == 1) t1 = r.render;
            std::printf("| %d | %.4f | %.2fx | %.0f%% |\n", t, r.render, t1 / r.render,
                        100.0 * t1 / r.render / t);
        }
        std::printf("\n");
    }
    {
        // Small sizes: the point is the ratio between accelerators, measured back to back.
        Scene base = load_scene(scene_path("dragon.xml"));
        base.set_resolution(quick ? 80 : 160, quick ? 60 : 120);
        std::printf(
            "### Accelerators inside the renderer (dragon.xml, %zu triangles, %dx%d, 1 thread)\n\n",
            base.num_triangles(), base.film.width, base.film.height);
        std::printf(
            "Trace share: intersect + occlusion stage time over all stages (photon tracing and "
            "final gathering also trace rays, inside their own stages).\n\n");
        std::printf(
            "| integrator | spp | bvh [s] | grid [s] | embree [s] | bvh rays/s | embree rays/s | "
            "bvh trace share | embree trace share | embree / bvh time |\n");
        std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
        struct Case {
            const char* label;
            const char* type;
            uint32_t spp;
            bool cache;
        };
        const Case cases[] = {{"whitted", "raytracer", 4, false},
                              {"path", "path", 4, false},
                              {"light", "light", 4, false},
                              {"photon (final gather)", "photon", 1, false},
                              {"photon (irradiance cache)", "photon", 1, true},
                              {"sppm", "sppm", 4, false}};
        for (const Case& c : cases) {
            const Scene& s = base;
            RenderSettings rs = render_settings(s);
            rs.integrator = c.type;
            rs.photon.global_photons = 50000;
            rs.photon.caustic_photons = 0;
            rs.photon.gather_rays = 16;
            rs.cache.samples = 128;
            rs.indirect = c.cache ? IndirectMode::IrradianceCache : IndirectMode::FinalGather;
            const Timing b = measure(s, rs, AccelType::Bvh, 1, c.spp, repeats);
            const Timing g = measure(s, rs, AccelType::Grid, 1, c.spp, repeats);
            const Timing e = measure(s, rs, AccelType::Embree, 1, c.spp, repeats);
            std::printf(
                "| %s | %u | %.4f | %.4f | %.4f | %.3g | %.3g | %.0f%% | %.0f%% | %.2fx |\n",
                c.label, c.spp, b.render, g.render, e.render, b.rays_per_s, e.rays_per_s,
                100.0 * b.trace_share, 100.0 * e.trace_share, e.render / b.render);
        }
        std::printf("\n");
    }
    return 0;
}
