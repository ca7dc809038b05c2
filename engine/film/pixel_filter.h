#pragma once
// The pixel reconstruction filter (pbrt-v4's PixelFilter): a pixel's value is the filter-
// weighted mean of the image around its centre. Camera paths importance-sample the filter
// (the film position of a sample is the pixel centre plus an offset drawn from f / integral),
// so every sample still counts once in its own pixel; light paths, which land anywhere on the
// film, splat to every pixel whose filter reaches them, weighted f(offset) / integral. The
// 1-pixel box is both the identity of the two (one pixel, weight 1) and what foton did before
// filters: its positions and splats are the same numbers, bit for bit.
//
// Box, triangle, Gaussian, Mitchell-Netravali and Lanczos are pbrt-v4's (separable; the
// Gaussian less its value at the radius, so it meets zero there). The last three are
// tabulated: each is the piecewise-linear function through 256 of its values per axis, for
// sampling and weighting alike, so the two sides agree exactly (it differs from the smooth
// curve by under 1e-4 of its peak). Mitchell and Lanczos are negative in places: camera samples
// are then placed by |f| and carry a signed weight, sign(f) times the integral of |f| over that
// of f (sample_weight; exactly that away from the few table steps where f changes sign), so a
// pixel's mean of weighted samples is still the filter-weighted mean of the image; splats take
// the signed f / integral.
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

enum class FilterType { Box, Triangle, Gaussian, Mitchell, Lanczos };
const char* filter_type_name(FilterType t);
// The type of a name as the scene formats and the command line write it; false if none.
bool parse_filter_type(const std::string& name, FilterType& t);
inline constexpr const char* kFilterTypeList = "box, triangle, gaussian, mitchell, lanczos";
// pbrt-v4's radius of each type when none is given (box 0.5, Gaussian 1.5, triangle and
// Mitchell 2, Lanczos 4), and its other parameters: Gaussian sigma 0.5, Mitchell b = c = 1/3,
// Lanczos tau 3.
float default_filter_radius(FilterType t);
struct FilterShape {
    float sigma = 0.5f;                  // Gaussian
    float b = 1.f / 3.f, c = 1.f / 3.f;  // Mitchell
    float tau = 3.f;                     // Lanczos
};

class PixelFilter {
  public:
    PixelFilter() = default;  // the 1-pixel box
    static PixelFilter box(float radius_x, float radius_y);
    static PixelFilter triangle(float radius_x, float radius_y);
    static PixelFilter gaussian(float radius_x, float radius_y, float sigma);
    // Mitchell and Netravali's cubic of parameters b and c, stretched over the radius.
    static PixelFilter mitchell(float radius_x, float radius_y, float b, float c);
    // sinc(x) sinc(x / tau) within the radius (a windowed sinc).
    static PixelFilter lanczos(float radius_x, float radius_y, float tau);
    // A filter of type t with the shape's parameter(s) its type reads.
    static PixelFilter make(FilterType t, float radius_x, float radius_y, const FilterShape& shape);

    FilterType type() const { return type_; }
    float radius_x() const { return axis_[0].radius; }
    float radius_y() const { return axis_[1].radius; }
    float sigma() const { return sigma_; }
    // Negative somewhere: camera samples carry sample_weight.
    bool negative_lobes() const {
        return type_ == FilterType::Mitchell || type_ == FilterType::Lanczos;
    }
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
    // The weight of a camera sample at position p in its pixel (as pixel_position gives it):
    // 1 unless the filter has negative lobes (see the top of this file).
    float sample_weight(Point2 p) const;

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
        float integral = 1.f;      // of f (signed)
        float mag_integral = 1.f;  // of |f|
        // Tabulated types: f at the nodes, |f| there, and the mass of |f| below each.
        std::vector<float> value, mag, cdf;
        float eval(FilterType t, float x) const;
        float sample(FilterType t, float u) const;
        float weight(float x) const;  // tabulated: f / |f| at x, times mag_integral / integral
        static float lerp(const std::vector<float>& nodes, float pos);
    };
    FilterType type_ = FilterType::Box;
    float sigma_ = 0.f;  // Gaussian: sigma; Mitchell: b; Lanczos: tau
    float c_ = 0.f;      // Mitchell: c
    Axis axis_[2];
    // Fills both axes' tables from f(x, radius).
    template <class F>
    void tabulate(F&& f);
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
            if (w != 0.f) add(uint32_t(y - y0) * uint32_t(width) + uint32_t(x - x0), w * inv);
        }
}

}  // namespace foton
