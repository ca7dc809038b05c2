#pragma once
// Light paths' splats through the pixel filter: what arrives at an image position goes to
// every film pixel the filter reaches from there, weighted f / integral (with the 1-pixel box:
// to the one pixel it lies in, unchanged). And the film positions of MLT's vectors, which
// land anywhere and splat the same way.
#include <vector>

#include "engine/film/pixel_sums.h"
#include "engine/scene/scene.h"

namespace foton {

inline void push_splats(const FilmSettings& film, FilmPoint at, const RGB& value,
                        std::vector<Splat>& out) {
    film.spread(at.x, at.y, [&](uint32_t pixel, float w) { out.push_back({pixel, value * w}); });
}

// Where a primary-sample vector's first two numbers put its camera sample: the film widened
// by the filter's reach on every side (pbrt-v4's sample bounds), so that an edge pixel gets
// its filter's whole support. A vector is one sample of this area.
struct FilmDomain {
    float x0, y0, width, height;  // relative to the film's corner, in pixels
    explicit FilmDomain(const FilmSettings& f) {
        const float m = f.filter.margin();
        x0 = -m;
        y0 = -m;
        width = float(f.width) + 2.f * m;
        height = float(f.height) + 2.f * m;
    }
    double area() const { return double(width) * double(height); }
    // The image position of numbers (u0, u1) in [0, 1).
    FilmPoint at(const FilmSettings& f, float u0, float u1) const {
        return {float(f.x0) + (x0 + u0 * width), float(f.y0) + (y0 + u1 * height)};
    }
};

}  // namespace foton
