#include "image_flags.h"

#include <algorithm>
#include <cmath>

#include "engine/core/error.h"
#include "engine/core/params.h"

namespace foton::app {

void apply_image_flags(const ImageFlags& args, Scene& scene) {
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
