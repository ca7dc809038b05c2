// foton: the command line. Subcommands render, info and compare.
#include <cstdio>
#include <exception>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "engine/core/error.h"
#include "engine/transport/registry/integrators.h"
#include "mpi_cluster.h"
#include "scale_study.h"
#include "serve.h"

int main(int argc, char** argv) {
    using namespace foton;
    CLI::App app{"foton: a research renderer for global illumination"};
    app.set_version_flag("--version", std::string("foton ") + FOTON_VERSION);
    app.require_subcommand(1);

    app::RenderArgs ra;
    CLI::App* render = app.add_subcommand("render", "render a scene to OpenEXR (+ PNG preview)");
    render->add_option("scene", ra.scene, "scene XML file")->required();
    render->add_option("-o,--output", ra.output, "output .exr (default out/<scene>.exr)");
    render->add_option("--preview", ra.preview,
                       "format of the tone-mapped image beside it: png (default), jpg, bmp");
    render->add_option("--spp", ra.spp, "samples per pixel (overrides aa_samples)");
    render->add_option("--threads", ra.threads, "worker threads (0 = all)");
    render->add_option("--seed", ra.seed, "random seed");
    render->add_option(
        "--accel", ra.accel,
        "brute | brute-simd | grid | bvh | embree | octree | kdtree (default: the scene's "
        "<aggregate>, else bvh)");
    render->add_option("--width", ra.width, "image width in pixels (keeps the field of view)");
    render->add_option("--height", ra.height, "image height in pixels");
    render
        ->add_option("--crop", ra.crop,
                     "x0,x1,y0,y1: render only this window, in fractions of the image (like "
                     "pbrt's --cropwindow); its pixels equal the full render's")
        ->delimiter(',');
    render
        ->add_option("--pixel-bounds", ra.pixel_bounds,
                     "x0,x1,y0,y1: render only pixels [x0,x1) x [y0,y1) (like pbrt's "
                     "--pixelbounds)")
        ->delimiter(',');
    render->add_option("--filter", ra.filter,
                       "pixel filter: box | triangle | gaussian | mitchell | lanczos, with "
                       ":radius (pixels), then gaussian :sigma, mitchell :b:c, lanczos :tau "
                       "(e.g. gaussian:1.5:0.5, pbrt-v4's default; mitchell:2:0.333:0.333); "
                       "replaces the scene's");
    render->add_option("--integrator", ra.integrator, "one of:" + integrator_help());
    render->add_option("--set", ra.set,
                       "key=value: set a <renderer> attribute (e.g. --set k=200 --set "
                       "filter=gauss); repeatable");
    render->add_option("--sampler", ra.sampler,
                       "regular | random | jittered | hammersley | sobol | halton | zsobol");
    render->add_option("--mis", ra.mis, "path: balance | power | max | none (NEE without MIS)");
    render->add_option("--aov", ra.aov,
                       "extra outputs as channels of the EXR: albedo, normal, depth, position, "
                       "variance, samples, components (photon mapping), comma-separated, or all");
    render->add_option("--nee", ra.nee, "path: next event estimation (false = BSDF sampling only)");
    render->add_option("--max-depth", ra.max_depth,
                       "scattering vertices (specular bounces for raytracer)");
    render->add_option("--rr-depth", ra.rr_depth, "Russian roulette from this depth on");
    render->add_option("--light-samples", ra.light_samples, "distributed: shadow rays per light");
    render->add_option("--time", ra.time, "render progressive passes for this many seconds");
    render->add_option("--passes", ra.passes,
                       "render this many progressive passes of --spp samples (SPPM/PPM: photon "
                       "passes); with --time, at most this many");
    render
        ->add_option("--snapshots", ra.snapshots,
                     "with --time or --passes: also write out-<t>s.exr after these many seconds")
        ->delimiter(',');
    render->add_option("--adaptive", ra.adaptive,
                       "adaptive sampling to this relative standard error (--spp = pilot)");
    render->add_option("--adaptive-max", ra.adaptive_max, "adaptive: most samples per pixel");
    render->add_flag("--adaptive-unbiased", ra.adaptive_unbiased,
                     "adaptive: Kirk-Arvo pilot (discarded) decides the count");
    render->add_flag("--stats", ra.stats, "print ray counts and the stage table");
    render->add_option("--stats-json", ra.stats_json, "write statistics as JSON");
    render->add_option("--cache-points", ra.cache_points,
                       "irradiance cache: also write this PNG, the image with the pixels where "
                       "records were computed in white");
    render->add_option("--reference", ra.reference,
                       "EXR: record after every pass the error to this image (RMSE, relMSE, "
                       "bias per channel) with wall and CPU time, as CSV and in --stats-json");
    render->add_option("--exclude-above", ra.exclude_above,
                       "with --reference: leave out pixels whose reference luminance is above "
                       "this (e.g. 2: the light)");
    render->add_option("--convergence", ra.convergence_csv,
                       "with --reference: the CSV to write (default <output>.convergence.csv)");
    render->add_option("--display", ra.display,
                       "HOST:PORT: stream the image after every pass to the tev viewer listening "
                       "there (start it with `tev --hostname 127.0.0.1:14158`)");
    render->add_flag("-q,--quiet", ra.quiet, "no progress bar or summary");
    render->add_flag("--pin", ra.pin,
                     "pin each thread to one CPU of those the process may use (physical cores "
                     "first): with mpirun --bind-to socket, a rank's threads stay on its socket");
    bool use_mpi = false;
    render->add_flag("--mpi", use_mpi,
                     "split the render across MPI ranks (automatic under mpirun/mpiexec/srun); "
                     "rank 0 writes the image, the same as one process's");

    std::string info_scene;
    CLI::App* info = app.add_subcommand("info", "print a scene summary");
    info->add_option("scene", info_scene, "scene XML file")->required();

    app::CompareArgs ca;
    CLI::App* compare = app.add_subcommand("compare", "error metrics between two EXR images");
    compare->add_option("a", ca.a, "image")->required();
    compare->add_option("b", ca.b, "reference image")->required();
    compare->add_option("--diff", ca.diff_png, "write a false-colour difference PNG");
    compare->add_option("--diff-scale", ca.diff_scale, "error that maps to white (default 0.1)");
    compare->add_option("--exclude-above", ca.exclude_above,
                        "leave out pixels whose luminance in b is above this (e.g. 2: the light)");
    compare
        ->add_option("--exclude-margin", ca.exclude_margin,
                     "with --exclude-above: also leave out pixels this close to those "
                     "(a light's partly covered edge)")
        ->check(CLI::Range(0, 64));
    compare->add_option("--mask", ca.mask_png, "PNG: count only its non-black pixels");
    compare
        ->add_option("--lowpass", ca.lowpass,
                     "also the RMSE after an N x N box filter of the error (N,...: the noise "
                     "left when neighbours are averaged; blue-noise samplers lower it)")
        ->delimiter(',')
        ->check(CLI::Range(1, 64));

    app::ServeArgs sa;
    app::ScaleArgs sc;
    CLI::App* scale = app.add_subcommand(
        "scale", "a scaling study: render at several thread counts, report speed-up per stage");
    scale->add_option("scene", sc.scene, "scene XML file")->required();
    scale->add_option("--threads", sc.threads,
                      "thread counts, increasing: 1,2,4,... (default and \"all\": powers of "
                      "two and every hardware thread)");
    scale->add_option("--integrator", sc.integrator, "as for render");
    scale->add_option("--set", sc.set, "key=value: set a <renderer> attribute; repeatable");
    scale->add_option("--spp", sc.spp, "samples per pixel (per pass with --passes or --time)");
    scale->add_option("--passes", sc.passes, "progressive passes (SPPM/PPM: photon passes)");
    scale->add_option("--time", sc.time,
                      "seconds of progressive passes per run: scaling by throughput");
    scale->add_option("--repeats", sc.repeats, "runs per thread count (median, min, max; 3)");
    scale->add_flag("--weak", sc.weak,
                    "weak scaling: the work (--passes if given, else spp) grows with the threads");
    scale->add_flag("--pin", sc.pin, "pin each thread to a CPU, physical cores first");
    scale->add_option("--accel", sc.accel,
                      "brute | brute-simd | grid | bvh | embree | octree | kdtree");
    scale->add_option("--width", sc.width, "image width in pixels");
    scale->add_option("--height", sc.height, "image height in pixels");
    scale->add_option("--seed", sc.seed, "random seed");
    scale->add_option("-o,--output", sc.json, "the study as JSON (default out/<scene>-scale.json)");
    scale->add_option("--plot", sc.plot, "SVG plot of speed-up and efficiency (default beside it)");

    CLI::App* serve = app.add_subcommand(
        "serve", "a local web page to open scenes, render, watch and save (one render at a time)");
    serve->add_option("--port", sa.port, "TCP port (0: any free one, printed); default 8080");
    serve->add_option("--host", sa.host,
                      "address to listen on; default 127.0.0.1 (this machine only); another "
                      "needs --allow-remote");
    serve->add_flag("--allow-remote", sa.allow_remote,
                    "let --host be an address other machines reach: anyone on that network can "
                    "then start renders");
    serve->add_option("--scenes", sa.scene_dirs,
                      "folders whose *.xml and *.pbrt scenes the page may open (default: scenes)");
    serve->add_option("--allow-read", sa.allow_read,
                      "folders besides --scenes whose files scenes may read (meshes, textures); "
                      "default with the default scenes: ../shared when it exists");

    try {
        app.parse(argc, argv);
        for (int i = 0; i < argc; ++i) ra.command_line += (i ? " " : "") + std::string(argv[i]);
        sc.command_line = ra.command_line;
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        app.exit(e);
        return kExitBadInput;
    }
    // Outlives the handlers below: MPI ends after the last message.
    std::optional<app::MpiRuntime> mpi;
    try {
        if (*render && (use_mpi || app::launched_by_mpi())) mpi.emplace();
        if (*render) return app::run_render(ra, mpi ? &mpi->cluster() : nullptr);
        if (*info) return app::run_info(info_scene);
        if (*compare) return app::run_compare(ca);
        if (*serve) return app::run_serve(sa);
        if (*scale) return app::run_scale(sc);
    } catch (const app::OtherRankFailed& e) {
        // Another MPI rank failed before the render: rank 0 says why.
        if (mpi && mpi->cluster().root()) std::fprintf(stderr, "%s\n", e.what());
        return kExitBadInput;
    } catch (const InputError& e) {
        return app::report_error(e.what(), kExitBadInput, true, mpi ? &*mpi : nullptr);
    } catch (const std::exception& e) {
        return app::report_error(std::string("foton: internal error: ") + e.what(), kExitInternal,
                                 false, mpi ? &*mpi : nullptr);
    }
    return kExitInternal;
}
