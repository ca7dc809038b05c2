#pragma once
// The command line's image flags: --width/--height (the field of view kept), a crop window
// (--crop in fractions, --pixel-bounds in pixels), checked against the image limits, and the
// pixel filter (--filter TYPE[:RADIUS[:SIGMA]], replacing the scene's).
#include <optional>
#include <string>
#include <vector>

#include "engine/scene/scene.h"

namespace foton::app {

struct ImageFlags {
    std::optional<std::string> width, height;  // as typed
    std::vector<double> crop;                  // x0,x1,y0,y1 in fractions of the image
    std::vector<int> pixel_bounds;             // x0,x1,y0,y1 in pixels
    std::string filter;                        // box | triangle | gaussian [:radius[:sigma]]
};

void apply_image_flags(const ImageFlags& args, Scene& scene);

}  // namespace foton::app
