#include "image_flags.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "engine/core/error.h"
#include "engine/core/params.h"

namespace foton::app {

namespace {

// --filter TYPE[:RADIUS[:...]]: gaussian[:radius[:sigma]], mitchell[:radius[:b:c]],
// lanczos[:radius[:tau]], box or triangle[:radius]; pbrt-v4's values unless given.
PixelFilter filter_flag(const std::string& text) {
    std::vector<std::string> part;
    std::size_t at = 0;
    for (std::size_t colon; (colon = text.find(':', at)) != std::string::npos; at = colon + 1)
        part.push_back(text.substr(at, colon - at));
    part.push_back(text.substr(at));
    FilterType kind;
    if (!parse_filter_type(part[0], kind))
        throw InputError("--filter", 0,
                         "unknown filter '" + part[0] + "' (" + kFilterTypeList + ")");
    const char* forms[] = {"box[:radius]", "triangle[:radius]", "gaussian[:radius[:sigma]]",
                           "mitchell[:radius[:b:c]]", "lanczos[:radius[:tau]]"};
    const std::size_t most[] = {2, 2, 3, 4, 3};
    const std::size_t k = std::size_t(kind);
    if (part.size() > most[k] || (kind == FilterType::Mitchell && part.size() == 3))
        throw InputError("--filter", 0, std::string("expected ") + forms[k]);
    // A radius, sigma or tau in (0, 16]; Mitchell's b and c in [0, 1].
    auto number = [&](std::size_t i, float fallback, const char* what, bool unit) {
        if (i >= part.size()) return fallback;
        char* end = nullptr;
        const float v = std::strtof(part[i].c_str(), &end);
        const bool ok = unit ? v >= 0.f && v <= 1.f : v > 0.f && v <= 16.f;
        if (part[i].empty() || *end != '\0' || !ok)
            throw InputError("--filter", 0,
                             std::string(what) + " '" + part[i] + "' must be a number in " +
                                 (unit ? "[0, 1]" : "(0, 16]"));
        return v;
    };
    const float r = number(1, default_filter_radius(kind), "the radius", false);
    FilterShape shape;
    if (kind == FilterType::Gaussian) shape.sigma = number(2, shape.sigma, "sigma", false);
    if (kind == FilterType::Lanczos) shape.tau = number(2, shape.tau, "tau", false);
    if (kind == FilterType::Mitchell) {
        shape.b = number(2, shape.b, "b", true);
        shape.c = number(3, shape.c, "c", true);
    }
    return PixelFilter::make(kind, r, r, shape);
}

}  // namespace

void apply_image_flags(const ImageFlags& args, Scene& scene) {
    if (!args.filter.empty()) scene.film.filter = filter_flag(args.filter);
    if (args.width || args.height) {
        const int w =
            args.width
                ? int(integer_or_fail(*args.width, 1, kMaxImageSide, "--width", 0, "the value"))
                : scene.film.width;
        const int h =
            args.height
                ? int(integer_or_fail(*args.height, 1, kMaxImageSide, "--height", 0, "the value"))
                : scene.film.height;
        check_image_size(w, h, "--width/--height", 0);
        scene.set_resolution(w, h);
    }
    if (!args.crop.empty() || !args.pixel_bounds.empty()) {
        const char* flag = args.crop.empty() ? "--pixel-bounds" : "--crop";
        if (!args.crop.empty() && !args.pixel_bounds.empty())
            throw InputError("--crop", 0, "give --crop or --pixel-bounds, not both");
        if (args.crop.size() != 4 && args.pixel_bounds.size() != 4)
            throw InputError(flag, 0, "expected four numbers x0,x1,y0,y1");
        const int w = scene.film.full_width, h = scene.film.full_height;
        int b[4];
        if (!args.crop.empty()) {
            for (double f : args.crop)
                if (!(f >= 0.0 && f <= 1.0))
                    throw InputError(flag, 0, "fractions must be in [0, 1]");
            // As pbrt's --cropwindow: both ends rounded up to whole pixels.
            b[0] = int(std::ceil(args.crop[0] * w));
            b[1] = int(std::ceil(args.crop[1] * w));
            b[2] = int(std::ceil(args.crop[2] * h));
            b[3] = int(std::ceil(args.crop[3] * h));
        } else {
            std::copy(args.pixel_bounds.begin(), args.pixel_bounds.end(), b);
        }
        if (!(0 <= b[0] && b[0] < b[1] && b[1] <= w && 0 <= b[2] && b[2] < b[3] && b[3] <= h))
            throw InputError(flag, 0,
                             "the window [" + std::to_string(b[0]) + "," + std::to_string(b[1]) +
                                 ") x [" + std::to_string(b[2]) + "," + std::to_string(b[3]) +
                                 ") is empty or outside the " + std::to_string(w) + "x" +
                                 std::to_string(h) + " image");
        scene.set_crop(b[0], b[1], b[2], b[3]);
    }
}

}  // namespace foton::app
