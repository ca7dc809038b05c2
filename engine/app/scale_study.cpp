#include "scale_study.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include "engine/accel/intersector.h"
#include "engine/core/cpu_topology.h"
#include "engine/core/error.h"
#include "engine/core/hash.h"
#include "engine/core/params.h"
#include "engine/core/thread_pinning.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/render.h"
#include "image_flags.h"
#include "output_paths.h"
#include "render_job.h"
#include "scale_report.h"
#include "scene_flags.h"

namespace foton::app {

namespace fs = std::filesystem;

namespace {

// Thread-seconds per graph node, or per stage when the render has no graph.
std::vector<std::pair<std::string, double>> stage_times(const RenderStats& st, int threads) {
    std::vector<std::pair<std::string, double>> out;
    for (const GraphStats::Node& n : st.graph.nodes)
        out.push_back({n.name, n.thread_time ? n.busy_seconds : n.busy_seconds * threads});
    if (out.empty())
        for (int i = 0; i < kNumStages; ++i)
            if (st.stage_seconds[i] > 0.0)
                out.push_back({stage_name(Stage(i)), st.stage_seconds[i]});
    return out;
}

}  // namespace

int run_scale(const ScaleArgs& args) {
    if (args.repeats < 1 || args.repeats > 1000)
        throw InputError("--repeats", 0, "must be from 1 to 1000");
    if (args.time && args.weak)
        throw InputError("--weak", 0, "needs fixed work (--spp or --passes), not --time");
    if (args.time && !(*args.time > 0.f)) throw InputError("--time", 0, "must be positive");
    JobRequest request{args.scene,  parse_set_flags(args.set),
                       args.accel,  {args.width, args.height, {}, {}, {}},
                       {},          args.spp,
                       args.passes, args.time,
                       {}};
    if (!args.integrator.empty())
        request.flags.push_back({"type", args.integrator, "--integrator"});
    if (args.seed) request.flags.push_back({"seed", *args.seed, "--seed"});
    const RenderJob job = make_job(request);
    const Scene& scene = job.scene;
    const RenderSettings& rs = job.settings;
    if (rs.adaptive.enabled)
        throw InputError(args.scene, 0, "adaptive sampling does not make a scaling study");
    const uint32_t passes = job.options.max_passes;

    const CpuTopology topo = cpu_topology();
    const std::vector<int> counts = thread_counts(args.threads, topo.logical);
    if (args.weak)
        for (const int n : counts)
            if (n % counts.front() != 0)
                throw InputError("--weak", 0,
                                 "every thread count must be a multiple of the first (the work "
                                 "grows by their ratio)");
    std::string json = args.json;
    if (json.empty())
        json = (fs::path("out") / fs::path(args.scene).stem()).string() + "-scale.json";
    std::string plot = args.plot;
    if (plot.empty()) plot = fs::path(json).replace_extension(".svg").string();
    check_writable(json, "-o", args.scene);
    check_writable(plot, "--plot", args.scene);

    ScaleStudy study;
    study.args = args;
    study.integrator = rs.integrator;
    study.accel = accel_name(scene.accel);
    study.width = scene.film.width;
    study.height = scene.film.height;
    study.settings = settings_text(scene);
    {
        std::ifstream in(args.scene, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), {});
        study.scene_hash = fnv1a(bytes.data(), bytes.size());
    }
    set_thread_pinning(args.pin);
    for (const int n : counts)
        for (uint32_t rep = 0; rep < args.repeats; ++rep) {
            // As `foton render`: progressive passes are one sample per pixel unless --spp.
            RenderOptions opt = job.options;
            opt.threads = n;
            if (args.weak) {
                const uint32_t scale = uint32_t(n / counts.front());
                if (passes)
                    opt.max_passes *= scale;
                else
                    opt.spp *= scale;
            }
            const auto t0 = std::chrono::steady_clock::now();
            const auto accel = make_intersector(scene, scene.accel, n);
            const double build =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            const RenderResult res = render(scene, rs, *accel, opt);
            ScaleRun r;
            r.threads = n;
            r.repeat = rep;
            r.wall_seconds = res.stats.wall_seconds;
            r.build_seconds = build;
            r.samples = res.stats.samples;
            r.passes = res.stats.passes;
            r.image_hash = fnv1a(res.film.pixels.data(), res.film.pixels.size() * sizeof(RGB));
            r.stage_thread_seconds = stage_times(res.stats, n);
            study.runs.push_back(r);
            std::fprintf(stderr, "foton scale: %d threads, run %u of %u: %.3f s\n", n, rep + 1,
                         args.repeats, r.wall_seconds);
        }
    set_thread_pinning(false);
    if (!args.time && !args.weak) {
        bool same = true;
        for (const ScaleRun& r : study.runs)
            same = same && r.image_hash == study.runs.front().image_hash;
        study.images_identical = same;
    }
    summarise(study);

    std::fputs(scale_markdown(study).c_str(), stdout);
    write_file_bytes(json, scale_json(study, topo));
    write_file_bytes(plot, scale_svg(study));
    std::printf("\nwrote %s\nwrote %s\n", json.c_str(), plot.c_str());
    if (study.images_identical == false) {
        std::fprintf(stderr,
                     "foton scale: the images differ between thread counts (they must not: "
                     "this is a bug)\n");
        return 1;
    }
    return 0;
}

}  // namespace foton::app
