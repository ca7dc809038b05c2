#pragma once
// A tile of the camera driver (camera_driver.h) and what an adaptive tile hands to the
// accumulation: per pixel of the tile (row-major in it) the radiance sum, the sample count,
// the moments of the variance AOV and the sums of the integrator's components.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "engine/core/rgb.h"
#include "engine/film/pixel_sums.h"

namespace foton {

struct Tile {
    int x0, y0, x1, y1;  // pixel rectangle [x0, x1) x [y0, y1)
    int pixels() const { return (x1 - x0) * (y1 - y0); }
};

inline std::vector<Tile> make_tiles(int width, int height, int size) {
    std::vector<Tile> tiles;
    for (int y = 0; y < height; y += size)
        for (int x = 0; x < width; x += size)
            tiles.push_back({x, y, std::min(x + size, width), std::min(y + size, height)});
    return tiles;
}

struct TileSums {
    std::vector<RGB> sum;
    std::vector<uint32_t> count;
    std::vector<SampleMoments> moments;
    std::vector<RGB> parts;  // `part_count` per pixel (the components AOV)
};

}  // namespace foton
