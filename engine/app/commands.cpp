#include "commands.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "engine/accel/intersector.h"
#include "engine/core/error.h"
#include "engine/film/image_io.h"
#include "engine/film/metrics.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/render.h"

namespace foton::app {

namespace fs = std::filesystem;

int run_render(const RenderArgs& args) {
    Scene scene = load_scene(args.scene);
    if (!args.accel.empty() && !parse_accel(args.accel, scene.accel))
        throw InputError(
            "--accel", 0,
            "unknown accelerator '" + args.accel + "' (brute, brute-simd, grid, embree)");
    if (args.width || args.height) {
        const int w = args.width.value_or(scene.film.width);
        const int h = args.height.value_or(scene.film.height);
        if (w <= 0 || h <= 0) throw InputError("--width/--height", 0, "must be positive");
        scene.set_resolution(w, h);
    }
    RenderOptions opt;
    opt.spp = args.spp.value_or(scene.render.spp);
    if (opt.spp == 0) throw InputError("--spp", 0, "must be at least 1");
    opt.threads = args.threads.value_or(scene.render.threads);
    if (opt.threads < 0) throw InputError("--threads", 0, "must not be negative");
    opt.seed = args.seed.value_or(scene.render.seed);
    opt.progress = !args.quiet;

    std::string out = args.output;
    if (out.empty()) out = (fs::path("out") / fs::path(args.scene).stem()).string() + ".exr";
    if (fs::path(out).extension() != ".exr")
        throw InputError(out, 0,
                         "output must be an .exr file (a .png preview is written beside it)");
    const fs::path out_dir = fs::path(out).parent_path();
    if (!out_dir.empty()) fs::create_directories(out_dir);
    const std::string png = fs::path(out).replace_extension(".png").string();

    const auto t0 = std::chrono::steady_clock::now();
    const std::unique_ptr<Intersector> accel = make_intersector(scene, scene.accel);
    const double build =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    RenderResult res = render(scene, *accel, opt);
    res.stats.build_seconds = build;

    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%.3f", res.stats.wall_seconds);
    const ImageAttributes attrs = {
        {"foton:scene", args.scene},
        {"foton:integrator", "whitted"},
        {"foton:samples", std::to_string(opt.spp)},
        {"foton:seed", std::to_string(opt.seed)},
        {"foton:renderSeconds", seconds},
        {"foton:threads", std::to_string(res.stats.threads)},
        {"foton:accel", accel->name()},
        {"foton:version", FOTON_VERSION},
    };
    write_exr(out, res.film, attrs);
    write_png(png, res.film, scene.camera.exposure, scene.film.gamma);
    if (!args.stats_json.empty()) {
        std::ofstream js(args.stats_json);
        if (!js) throw InputError(args.stats_json, 0, "cannot write statistics file");
        js << res.stats.json();
    }
    if (args.stats) std::fputs(res.stats.table().c_str(), stdout);
    if (!args.quiet)
        std::printf("rendered %s (%dx%d, %u spp, %s, %d threads) in %.3f s\nwrote %s\nwrote %s\n",
                    args.scene.c_str(), scene.film.width, scene.film.height, opt.spp, accel->name(),
                    res.stats.threads, res.stats.wall_seconds, out.c_str(), png.c_str());
    return 0;
}

int run_info(const std::string& path) {
    const Scene scene = load_scene(path);
    std::fputs(scene.summary().c_str(), stdout);
    return 0;
}

int run_compare(const CompareArgs& args) {
    const Film a = read_exr(args.a);
    const Film b = read_exr(args.b);
    if (a.width != b.width || a.height != b.height)
        throw InputError(args.b, 0,
                         "image is " + std::to_string(b.width) + "x" + std::to_string(b.height) +
                             ", the first is " + std::to_string(a.width) + "x" +
                             std::to_string(a.height));
    const ImageError e = compare_images(a, b);
    std::printf("rmse %.6g\nrelative_mse %.6g\nmae %.6g\nmax_abs %.6g\npixels %zu\n", e.rmse,
                e.relative_mse, e.mae, e.max_abs, e.pixels);
    if (!args.diff_png.empty()) write_difference_png(args.diff_png, a, b, args.diff_scale);
    return 0;
}

}  // namespace foton::app
