#pragma once
// A tile of the camera driver (camera_driver.h) and what an adaptive tile hands to the
// accumulation: per pixel of the tile (row-major in it) the radiance sum, the sample count,
// the moments of the variance AOV and the sums of the integrator's components.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "engine/core/rgb.h"
#include "engine/film/pixel_sums.h"
#include "engine/scene/scene.h"
#include "engine/transport/common/camera_integrator.h"

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

// Appends the samples [s0, s1) of every pixel of `t` in pass `pass` of `spp` samples per pixel:
// the one place that numbers camera samples (a pattern point and an id unique in the image),
// so the first-hit AOVs' pass traces the very rays of the render's first pass.
inline void append_pass_jobs(const FilmSettings& film, const Tile& t, uint32_t pass, uint32_t s0,
                             uint32_t s1, uint32_t spp, std::vector<SampleJob>& jobs) {
    const uint64_t npix = film.full_pixels();
    for (int y = t.y0; y < t.y1; ++y)
        for (int x = t.x0; x < t.x1; ++x) {
            const uint64_t pixel = film.pixel_id(uint32_t(x), uint32_t(y));
            for (uint32_t s = s0; s < s1; ++s)
                jobs.push_back({uint32_t(x), uint32_t(y), s, spp, pass,
                                (uint64_t(pass) * npix + pixel) * spp + s});
        }
}

struct TileSums {
    std::vector<RGB> sum;
    std::vector<uint32_t> count;
    std::vector<SampleMoments> moments;
    std::vector<RGB> parts;      // `part_count` per pixel (the components AOV)
    std::vector<double> weight;  // a filter with negative lobes: the samples' weights' sum
};

}  // namespace foton
