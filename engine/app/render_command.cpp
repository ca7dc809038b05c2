// `foton render`: a scene to an OpenEXR image and its preview, in one process or split
// across MPI ranks (rank 0 writes; see mpi_cluster.h for how errors end every rank).
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include <unistd.h>

#include "build_info.h"
#include "commands.h"
#include "convergence_log.h"
#include "engine/accel/intersector.h"
#include "engine/core/cpu_topology.h"
#include "engine/core/error.h"
#include "engine/core/stats_wire.h"
#include "engine/core/thread_pinning.h"
#include "engine/film/image_io.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/render.h"
#include "image_flags.h"
#include "interrupt.h"
#include "job_agreement.h"
#include "kernels/simd.h"
#include "mpi_cluster.h"
#include "output_paths.h"
#include "progress_line.h"
#include "render_job.h"
#include "scene_flags.h"
#include "tev_display.h"

namespace foton::app {

namespace fs = std::filesystem;

namespace {

// The shortest text that reads back as exactly v.
std::string exact_text(float v) {
    char buf[32];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
    return ec == std::errc() ? std::string(buf, end) : std::to_string(v);
}

// The image with every directly visible first-level cache record drawn as a white pixel (the
// thesis' figure of computed vs interpolated points). Records seen only through a mirror or
// glass are behind it, hence hidden.
Film mark_cache_points(const Scene& scene, const Intersector& accel, const Film& film,
                       const std::vector<Vec3>& points, std::size_t& marked) {
    Film f = film;
    TraceCounters counters;
    marked = 0;
    for (const Vec3& p : points) {
        float fx, fy;
        if (!scene.camera.project(p, fx, fy)) continue;
        Vec3 o, d;
        scene.camera.generate(fx, fy, o, d);
        const Vec3 to = p - o;
        const float dist = length(to);
        const Vec3 u = to * (1.f / dist);
        if (accel.occluded1({o.x, o.y, o.z, u.x, u.y, u.z, 0.f, dist * (1.f - 1e-3f)}, counters))
            continue;
        const int x = std::min(int(fx) - scene.film.x0, film.width - 1);
        const int y = std::min(int(fy) - scene.film.y0, film.height - 1);
        f.pixels[std::size_t(y) * film.width + x] = RGB{1e4f};
        ++marked;
    }
    return f;
}

// Where this rank runs: a multi-node run's statistics say which node was slow.
std::string host_name() {
    char name[256] = {};
    if (gethostname(name, sizeof name - 1) != 0) return "unknown";
    return name;
}

// Rank 0 gets every rank's counters (merged into `stats`) and each rank's own statistics, as
// a JSON list; null in one process. Collective.
nlohmann::ordered_json gather_rank_stats(const Cluster& ranks, RenderStats& stats) {
    if (!ranks.distributed()) return nullptr;
    const std::string own_text =
        stats.json({{"rank", ranks.rank()},
                    {"host", host_name()},
                    {"mpi_bytes_moved", ranks.bytes_moved()},
                    {"mpi_collective_seconds", ranks.collective_seconds()}});
    Bytes mine;
    pack_counters(mine, stats);
    pack(mine, std::vector<char>(own_text.begin(), own_text.end()));
    const std::vector<Bytes> parts = ranks.gather(mine);
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (std::size_t r = 0; r < parts.size(); ++r) {
        Unpacker in(parts[r]);
        const RenderStats counters = unpack_counters(in);
        if (r > 0) stats.merge(counters);
        std::vector<char> text;
        in.append(text);
        list.push_back(nlohmann::ordered_json::parse(text.begin(), text.end()));
    }
    return list;
}

// The job as the flags ask for it: the flags that are renderer settings join the file's and
// --set's in the scene's set, checked by the same rules, reported under their own name,
// recorded with the others.
JobRequest job_request(const RenderArgs& args) {
    JobRequest request{
        args.scene,  parse_set_flags(args.set),
        args.accel,  {args.width, args.height, args.crop, args.pixel_bounds, args.filter},
        {},          args.spp,
        args.passes, args.time,
        {}};
    auto flag = [&](const char* key, const std::string& value, const char* name) {
        request.flags.push_back({key, value, name});
    };
    if (!args.integrator.empty()) flag("type", args.integrator, "--integrator");
    if (!args.mis.empty()) flag("mis", args.mis, "--mis");
    if (!args.aov.empty()) flag("aov", args.aov, "--aov");
    if (!args.sampler.empty()) flag("sampler", args.sampler, "--sampler");
    if (args.nee) flag("nee", *args.nee ? "true" : "false", "--nee");
    if (args.max_depth) flag("max_depth", std::to_string(*args.max_depth), "--max-depth");
    if (args.rr_depth) flag("rr_depth", std::to_string(*args.rr_depth), "--rr-depth");
    if (args.light_samples)
        flag("light_samples", std::to_string(*args.light_samples), "--light-samples");
    if (args.adaptive) {
        flag("adaptive", "true", "--adaptive");
        flag("adaptive_threshold", exact_text(*args.adaptive), "--adaptive");
    }
    if (args.adaptive_max)
        flag("adaptive_max_spp", std::to_string(*args.adaptive_max), "--adaptive-max");
    if (args.adaptive_unbiased) flag("adaptive_unbiased", "true", "--adaptive-unbiased");
    // Numbers are parsed by the settings' one integer parser, whatever wrote them.
    if (args.seed) flag("seed", *args.seed, "--seed");
    if (args.threads) flag("num_threads", *args.threads, "--threads");
    return request;
}

// Where the render writes: the EXR (out/<scene>.exr unless -o), its preview beside it in
// the --preview format.
struct RenderOutputs {
    std::string exr, preview;
    PreviewFormat preview_format = PreviewFormat::Png;
};
RenderOutputs render_outputs(const RenderArgs& args) {
    RenderOutputs o;
    o.exr = args.output;
    if (o.exr.empty()) o.exr = (fs::path("out") / fs::path(args.scene).stem()).string() + ".exr";
    if (fs::path(o.exr).extension() != ".exr")
        throw InputError(o.exr, 0,
                         "output must be an .exr file (a .png preview is written beside it)");
    if (!args.preview.empty() && !preview_formats().parse(args.preview, o.preview_format))
        throw InputError(
            "--preview", 0,
            "unknown format '" + args.preview + "' (" + preview_formats().list() + ")");
    o.preview = fs::path(o.exr).replace_extension(preview_extension(o.preview_format)).string();
    return o;
}

// A snapshot's file beside the output: out-10s.exr for the one requested at 10 s.
std::string snapshot_path(const std::string& exr, double requested) {
    char suffix[48];
    std::snprintf(suffix, sizeof suffix, "-%gs.exr", requested);
    return fs::path(exr).replace_extension("").string() + suffix;
}

// What the statistics JSON says about the run before its counters: build, scene, settings,
// machine.
nlohmann::ordered_json run_record(const RenderArgs& args, const Scene& scene,
                                  const RenderSettings& rs, const RenderOptions& opt,
                                  const char* accel, double spp_mean, int ranks) {
    return {
        {"version", FOTON_VERSION},
        {"git_commit", git_commit()},
        {"scene", args.scene},
        {"integrator", rs.integrator},
        {"accelerator", accel},
        {"width", scene.film.width},
        {"height", scene.film.height},
        {"spp_mean", spp_mean},
        {"seed", opt.seed},
        {"threads_requested", opt.threads},
        {"cpu", cpu_topology().model},
        {"hardware_threads", std::thread::hardware_concurrency()},
        {"simd", simd::Arch::name()},
        {"simd_width", simd::kWidth},
        {"mpi_ranks", ranks},
        {"pinned", args.pin},
    };
}

}  // namespace

int run_render(const RenderArgs& args, const Cluster* cluster) {
    // Across MPI ranks every rank loads and checks the same input; rank 0 alone writes
    // files, shows progress and feeds the observers (the render gathers the image to it).
    const Cluster& ranks = cluster_or_solo(cluster);
    const bool root = ranks.root();
    // Every arena the render and the accelerator's build make is pinned (PinnedArena).
    set_thread_pinning(args.pin);
    RenderJob made = make_job(job_request(args));
    Scene& scene = made.scene;
    const RenderSettings& rs = made.settings;
    RenderOptions& opt = made.options;
    const bool progressive = made.progressive;
    if (!args.quiet && root)
        for (const std::string& w : scene.warnings)
            std::fprintf(stderr, "foton: warning: %s\n", w.c_str());
    opt.snapshot_times = args.snapshots;
    for (const double t : opt.snapshot_times)
        if (!(t > 0.0) || !std::isfinite(t))
            throw InputError("--snapshots", 0,
                             "snapshot times are seconds after the start, positive and finite");
    if (!opt.snapshot_times.empty() && !progressive)
        throw InputError("--snapshots", 0,
                         "needs --time or --passes (snapshots are taken between the passes of "
                         "a progressive render)");
    // Progress goes to stderr when it is a terminal, never into a file or a pipe.
    Progress progress;
    opt.progress = &progress;
    std::unique_ptr<ProgressLine> line;
    if (!args.quiet && root && isatty(fileno(stderr)))
        line = std::make_unique<ProgressLine>(progress);

    const RenderOutputs outputs = render_outputs(args);
    const std::string& out = outputs.exr;
    const std::string& png = outputs.preview;
    FilePlan files;
    files.input(args.scene, "the scene file");
    files.input(args.reference, "the --reference image");
    if (root) {
        files.output(out, "-o");
        files.output(png, "-o (its preview)");
        if (!args.stats_json.empty()) files.output(args.stats_json, "--stats-json");
        if (!args.cache_points.empty()) files.output(args.cache_points, "--cache-points");
        for (const double t : opt.snapshot_times)
            files.output(snapshot_path(out, t), "--snapshots");
    }
    const JobRecord job{args.scene, args.command_line};
    auto attributes = [&](double seconds, uint32_t passes, double spp, const char* accel_name) {
        return job_attributes(job, scene, rs, opt, seconds, passes, spp, accel_name);
    };
    auto exr_info = [&](double seconds, double spp) { return job_exr_info(scene, seconds, spp); };
    if (!opt.snapshot_times.empty()) {
        opt.on_snapshot = [&](const Film& f, double requested, double seconds, uint32_t passes,
                              double spp) {
            write_exr(snapshot_path(out, requested), f,
                      attributes(seconds, passes, spp, accel_name(scene.accel)),
                      exr_info(seconds, spp));
        };
    }

    // Observers of every pass: convergence against a reference.
    std::unique_ptr<ConvergenceLog> convergence;
    std::string convergence_csv = args.convergence_csv;
    if (!args.reference.empty()) {
        if (root)
            convergence =
                std::make_unique<ConvergenceLog>(args.reference, scene.film, args.exclude_above);
        if (convergence_csv.empty())
            convergence_csv = fs::path(out).replace_extension(".convergence.csv").string();
        if (root) files.output(convergence_csv, "--convergence");
    } else if (args.exclude_above || !args.convergence_csv.empty()) {
        throw InputError(args.exclude_above ? "--exclude-above" : "--convergence", 0,
                         "needs --reference");
    }
    // And the live preview.
    std::unique_ptr<TevDisplay> display;
    if (!args.display.empty() && root)
        display = std::make_unique<TevDisplay>(args.display, fs::path(out).filename().string(),
                                               scene.film.width, scene.film.height,
                                               aov_channels(rs.aovs));
    // Only when something observes: the image of every pass costs a gather across ranks.
    if (convergence || display)
        opt.on_pass = [&](const Film& film, const PassReport& pass) {
            if (convergence) convergence->record(film, pass);
            if (display) display->show(film);
        };

    if (!args.cache_points.empty() && rs.indirect != IndirectMode::IrradianceCache)
        throw InputError("--cache-points", 0, "needs indirect=irradiance_cache");
    const auto t0 = std::chrono::steady_clock::now();
    // The accelerator's own pool (Embree's) gets the same bound as the render's.
    std::unique_ptr<Intersector> accel;
    {
        const ProgressTask task(&progress, "build-accelerator", 0);
        accel = make_intersector(scene, scene.accel, resolve_threads(opt.threads));
    }
    const double build =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // Every rank is ready (or all stop here), and all loaded the same job: the render's
    // collectives begin.
    check_in(ranks);
    agree_on_job(ranks, job_fingerprint(args.scene, made), args.scene);
    set_rank_phase(RankPhase::Collective);
    if (ranks.distributed()) opt.cluster = &ranks;
    // Ctrl-C from here on stops the render and keeps what it made.
    InterruptGuard interrupt;
    opt.cancel = &InterruptGuard::requested();
    RenderResult res = render(scene, rs, *accel, opt);
    // A signal may have reached one rank only: its share of the pass is missing, so the
    // image is an interrupted one on every rank.
    const bool interrupted = ranks.any(InterruptGuard::requested().load());
    line.reset();
    if (display && rs.aovs) {
        std::vector<AovLayer> layers = res.aovs;
        if ((rs.aovs & kAovSamples) && res.samples_per_pixel.size() == res.film.pixels.size())
            layers.push_back(samples_layer(res.samples_per_pixel));
        display->show_layers(std::move(layers));
    }
    display.reset();  // the last pass's image (and the AOVs) reach the viewer
    res.stats.build_seconds = build;
    const nlohmann::ordered_json rank_stats = gather_rank_stats(ranks, res.stats);
    set_rank_phase(RankPhase::Local);
    if (!root) return interrupted ? kExitInterrupted : 0;

    const double spp_mean = mean_samples(res);
    if (interrupted && !(spp_mean > 0.0)) {
        // Stopped before any sample reached the image (in a pre-pass: photons, the cache
        // fill, the guide): a black image would only replace a previous result.
        std::fprintf(stderr,
                     "foton: interrupted before any sample reached the image: nothing was "
                     "written\n");
        return kExitInterrupted;
    }
    ImageAttributes attrs =
        attributes(res.stats.wall_seconds, res.stats.passes, spp_mean, accel->name());
    attrs.push_back({"foton:threads", std::to_string(res.stats.threads)});
    if (ranks.distributed()) attrs.push_back({"foton:mpiRanks", std::to_string(ranks.size())});
    if (interrupted) attrs.push_back({"foton:interrupted", "true"});
    ExrRenderInfo info = exr_info(res.stats.wall_seconds, spp_mean);
    const SampleSpread spread = describe_sample_counts(res, attrs, info, rs.aovs);
    // With --reference, pbrt-v4's MSE of the written image (the last pass's error).
    if (convergence && !convergence->points().empty()) {
        const double rmse = convergence->points().back().error.rmse;
        info.mse = float(rmse * rmse);
    }
    write_exr(out, res.film, attrs, info);
    write_preview(png, res.film, scene.camera.exposure, scene.film.gamma, outputs.preview_format);
    if (!args.cache_points.empty()) {
        std::size_t marked = 0;
        const Film f = mark_cache_points(scene, *accel, res.film, res.cache_points, marked);
        write_png(args.cache_points, f, scene.camera.exposure, scene.film.gamma);
        if (!args.quiet)
            std::printf("wrote %s (%zu of %zu records directly visible)\n",
                        args.cache_points.c_str(), marked, res.cache_points.size());
    }
    if (convergence) write_file_bytes(convergence_csv, convergence->csv());
    if (!args.stats_json.empty()) {
        nlohmann::ordered_json run =
            run_record(args, scene, rs, opt, accel->name(), spp_mean, ranks.size());
        // Across ranks: the counters above are every rank's summed, times are rank 0's,
        // and each rank's own statistics follow.
        if (ranks.distributed()) run["ranks"] = rank_stats;
        if (convergence) {
            run["reference"] = args.reference;
            run["convergence"] = convergence->json();
        }
        write_file_bytes(args.stats_json, res.stats.json(run));
    }
    if (args.stats) std::fputs(res.stats.table().c_str(), stdout);
    if (!args.quiet)
        std::printf(
            "rendered %s with %s (%dx%d, %.4g spp in %u passes, %s, %d threads%s) in %.3f s\n"
            "wrote %s\nwrote %s\n",
            args.scene.c_str(), integrator_label(rs).c_str(), scene.film.width, scene.film.height,
            double(res.stats.samples) / (double(scene.film.width) * scene.film.height),
            res.stats.passes, accel->name(), res.stats.threads,
            ranks.distributed() ? (" x " + std::to_string(ranks.size()) + " MPI ranks").c_str()
                                : "",
            res.stats.wall_seconds, out.c_str(), png.c_str());
    if (convergence && !args.quiet) std::printf("wrote %s\n", convergence_csv.c_str());
    if (interrupted) {
        std::fprintf(stderr,
                     "foton: interrupted after %u passes (%.4g spp on average): the image "
                     "so far was written\n",
                     res.stats.passes, spp_mean);
        if (spread.uneven())
            std::fprintf(stderr,
                         "foton: the pass was cut short: pixels hold %u to %u samples, %zu of "
                         "%zu none (the EXR's `samples` channel holds each pixel's count)\n",
                         spread.fewest, spread.most, spread.none, res.film.pixels.size());
        return kExitInterrupted;
    }
    // A signal during the writes: they finished (the image is whole), but the exit code says
    // the run was interrupted.
    if (InterruptGuard::requested().load()) return kExitInterrupted;
    return 0;
}

}  // namespace foton::app
