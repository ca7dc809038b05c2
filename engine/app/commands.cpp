// `foton info` and `foton compare` (`foton render` is render_command.cpp).
#include "commands.h"

#include <cstdio>
#include <vector>

#include "engine/film/image_io.h"
#include "engine/film/metrics.h"
#include "engine/film/ssim.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/render.h"
#include "output_paths.h"

namespace foton::app {

int run_info(const std::string& path) {
    const Scene scene = load_scene(path);
    const RenderSettings rs = render_settings(scene);
    std::fputs(scene.summary().c_str(), stdout);
    std::printf("renderer   %s, %u spp (%s), depth %u, accel %s\n", integrator_label(rs).c_str(),
                rs.run.spp, sampler_name(rs.sampler), rs.max_depth, accel_name(scene.accel));
    return 0;
}

int run_compare(const CompareArgs& args) {
    if (!args.diff_png.empty()) {
        FilePlan files;
        files.input(args.a, "the first image");
        files.input(args.b, "the second image");
        files.output(args.diff_png, "--diff");
    }
    const Film a = read_exr(args.a);
    Film b = read_exr(args.b);
    if (a.width != b.width || a.height != b.height) {
        // A reference at an integer multiple of the resolution is box-filtered down.
        const int factor = a.width > 0 ? b.width / a.width : 0;
        b = fit_reference(std::move(b), a.width, a.height, args.b);
        std::printf("reference downsampled %dx to %dx%d\n", factor, b.width, b.height);
    }
    std::vector<uint8_t> mask(a.pixels.size(), 1);
    if (args.exclude_above)
        mask = grow_exclusion(luminance_mask(b, *args.exclude_above), b.width, b.height,
                              args.exclude_margin);
    if (!args.mask_png.empty()) {
        const std::vector<uint8_t> m = read_png_mask(args.mask_png, a.width, a.height);
        for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = mask[i] && m[i];
    }
    const ImageError e = compare_images(a, b, &mask);
    std::printf("rmse %.6g\nrelative_mse %.6g\nmae %.6g\nmax_abs %.6g\npixels %zu\n", e.rmse,
                e.relative_mse, e.mae, e.max_abs, e.pixels);
    std::printf("mean_a %.6g %.6g %.6g\nmean_b %.6g %.6g %.6g\n", e.mean_a.r, e.mean_a.g,
                e.mean_a.b, e.mean_b.r, e.mean_b.g, e.mean_b.b);
    std::printf("nonfinite_a %zu\nnonfinite_b %zu\n", e.nonfinite_a, e.nonfinite_b);
    // Structural similarity of the display values (at exposure 1), over the same mask.
    std::printf("ssim %.6g\n", ssim(a, b, &mask));
    for (int n : args.lowpass)
        std::printf("lowpass_rmse %d %.6g\n", n, lowpass_rmse(a, b, mask, n));
    if (!args.diff_png.empty()) write_difference_png(args.diff_png, a, b, args.diff_scale);
    // Not-a-number or infinite pixels make the figures meaningless: say so in the exit code.
    if (e.nonfinite_a || e.nonfinite_b) {
        std::fprintf(stderr, "foton compare: %zu pixels of %s and %zu of %s are NaN or infinite\n",
                     e.nonfinite_a, args.a.c_str(), e.nonfinite_b, args.b.c_str());
        return 3;
    }
    return 0;
}

}  // namespace foton::app
