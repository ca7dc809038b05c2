#pragma once
// The pixel reconstruction filter (pbrt-v4's PixelFilter): a pixel's value is the filter-
// weighted mean of the image around its centre. Camera paths importance-sample the filter
// (the film position of a sample is the pixel centre plus an offset drawn from f / integral),
// so every sample still counts once in its own pixel; light paths, which land anywhere on the
// film, splat to every pixel whose filter reaches them, weighted f(offset) / integral. The
// 1-pixel box is both the identity of the two (one pixel, weight 1) and what foton did before
// filters: its positions and splats are the same numbers, bit for bit.
//
// Box, triangle and Gaussian are pbrt-v4's (separable; the Gaussian less its value at the
// radius, so it meets zero there). The Gaussian is tabulated: it is the piecewise-linear
// function through 256 of its values per axis, for sampling and weighting alike, so the two
// sides agree exactly (it differs from the smooth curve by under 1e-4 of its peak). Mitchell
// and Lanczos, negative in places, would need signed sample weights and are not offered.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/core/sampler.h"

namespace foton {

// An image position in pixels, (0, 0) the image's top-left corner: where a light path's
// splat lands before the filter spreads it over pixels.
struct FilmPoint {
    float x = 0.f, y = 0.f;
};

enum class FilterType { Box, Triangle, Gaussian };
const char* filter_type_name(FilterType t);

class PixelFilter {
  public:
    PixelFilter() = default;  // the 1-pixel box
    static PixelFilter box(float radius_x, float radius_y);
    static PixelFilter triangle(float radius_x, float radius_y);
    static PixelFilter gaussian(float radius_x, float radius_y, float sigma);

    FilterType type() const { return type_; }
    float radius_x() const { return axis_[0].radius; }
    float radius_y() const { return axis_[1].radius; }
    float sigma() const { return sigma_; }
    // The 1-pixel box: each sample and splat belongs to the pixel it lies in.
    bool unit_box() const {
        return type_ == FilterType::Box && radius_x() == 0.5f && radius_y() == 0.5f;
    }
    // How far outside the film a point still reaches a film pixel (0 for the 1-pixel box).
    float margin() const;

    // The filter at offset (dx, dy) from a pixel centre, and its integral over the plane.
    float eval(float dx, float dy) const;
    float integral() const { return axis_[0].integral * axis_[1].integral; }
    // A camera sample's position in its pixel, (0, 0) the pixel's corner: the sampler's
    // point u itself for the 1-pixel box, else the centre plus an offset drawn from the
    // filter (separably, so stratified points stay stratified).
    Point2 pixel_position(Point2 u) const;

    // Calls add(film pixel index, weight) for every pixel of the film [x0, x0 + width) x
    // [y0, y0 + height) (image pixels) whose filter reaches image position (fx, fy), weight
    // f / integral.
    template <class Add>
    void spread(float fx, float fy, int x0, int y0, int width, int height, Add&& add) const;

    std::string describe() const;

  private:
    // One axis: its radius and, for the tabulated and triangle types, what sampling needs.
    struct Axis {
        float radius = 0.5f;
        float integral = 1.f;
        std::vector<float> value, cdf;  // Gaussian: values at the nodes, mass below each
        float eval(FilterType t, float x) const;
        float sample(FilterType t, float u) const;
    };
    FilterType type_ = FilterType::Box;
    float sigma_ = 0.f;
    Axis axis_[2];
    void tabulate(float sigma);
};

template <class Add>
void PixelFilter::spread(float fx, float fy, int x0, int y0, int width, int height,
                         Add&& add) const {
    if (unit_box()) {
        // The pixel the point lies in.
        if (fx < float(x0) || fy < float(y0) || fx >= float(x0 + width) || fy >= float(y0 + height))
            return;
        const int x = int(fx) - x0, y = int(fy) - y0;
        add(uint32_t(y) * uint32_t(width) + uint32_t(x), 1.f);
        return;
    }
    const float rx = radius_x(), ry = radius_y(), inv = 1.f / integral();
    // Pixels whose centre (X + 0.5) lies within the radius.
    const int xa = std::max(x0, int(std::ceil(fx - 0.5f - rx))),
              xb = std::min(x0 + width - 1, int(std::floor(fx - 0.5f + rx)));
    const int ya = std::max(y0, int(std::ceil(fy - 0.5f - ry))),
              yb = std::min(y0 + height - 1, int(std::floor(fy - 0.5f + ry)));
    for (int y = ya; y <= yb; ++y)
        for (int x = xa; x <= xb; ++x) {
            const float w = eval(float(x) + 0.5f - fx, float(y) + 0.5f - fy);
            if (w > 0.f) add(uint32_t(y - y0) * uint32_t(width) + uint32_t(x - x0), w * inv);
        }
}

}  // namespace foton
