#include "pixel_filter.h"

#include <cstdio>

#include "engine/core/math.h"

namespace foton {

namespace {

constexpr int kNodes = 256;  // Gaussian table intervals per axis

float gaussian_at(float x, float sigma) {
    return std::exp(-x * x / (2.f * sigma * sigma)) / (std::sqrt(2.f * kPi) * sigma);
}

}  // namespace

const char* filter_type_name(FilterType t) {
    switch (t) {
        case FilterType::Box:
            return "box";
        case FilterType::Triangle:
            return "triangle";
        case FilterType::Gaussian:
            return "gaussian";
    }
    return "?";
}

PixelFilter PixelFilter::box(float rx, float ry) {
    PixelFilter f;
    f.axis_[0].radius = rx;
    f.axis_[1].radius = ry;
    for (Axis& a : f.axis_) a.integral = 2.f * a.radius;
    return f;
}

PixelFilter PixelFilter::triangle(float rx, float ry) {
    PixelFilter f = box(rx, ry);
    f.type_ = FilterType::Triangle;
    for (Axis& a : f.axis_) a.integral = a.radius * a.radius;
    return f;
}

PixelFilter PixelFilter::gaussian(float rx, float ry, float sigma) {
    PixelFilter f = box(rx, ry);
    f.type_ = FilterType::Gaussian;
    f.sigma_ = sigma;
    f.tabulate(sigma);
    return f;
}

void PixelFilter::tabulate(float sigma) {
    for (Axis& a : axis_) {
        const float r = a.radius, h = 2.f * r / float(kNodes), floor = gaussian_at(r, sigma);
        a.value.resize(kNodes + 1);
        a.cdf.assign(kNodes + 1, 0.f);
        for (int i = 0; i <= kNodes; ++i)
            a.value[std::size_t(i)] = std::max(0.f, gaussian_at(-r + h * float(i), sigma) - floor);
        // Trapezoids: exact for the piecewise-linear function the table is.
        double mass = 0.0;
        for (std::size_t i = 0; i < kNodes; ++i) {
            mass += 0.5 * double(h) * (double(a.value[i]) + double(a.value[i + 1]));
            a.cdf[i + 1] = float(mass);
        }
        a.integral = float(mass);
    }
}

float PixelFilter::Axis::eval(FilterType t, float x) const {
    const float ax = std::fabs(x);
    if (ax > radius) return 0.f;
    if (t == FilterType::Box) return 1.f;
    if (t == FilterType::Triangle) return radius - ax;
    const float pos = (x + radius) / (2.f * radius) * float(kNodes);
    const int i = std::clamp(int(pos), 0, kNodes - 1);
    const float f = pos - float(i);
    return value[std::size_t(i)] * (1.f - f) + value[std::size_t(i) + 1] * f;
}

float PixelFilter::Axis::sample(FilterType t, float u) const {
    const float r = radius;
    if (t == FilterType::Box) return r * (2.f * u - 1.f);
    if (t == FilterType::Triangle)
        return u < 0.5f ? -r + r * std::sqrt(2.f * u) : r - r * std::sqrt(2.f * (1.f - u));
    // The interval holding mass u * integral, then the linear piece inverted in it.
    const float m = u * integral;
    const auto it = std::upper_bound(cdf.begin(), cdf.end(), m);
    const int i = std::clamp(int(it - cdf.begin()) - 1, 0, kNodes - 1);
    const float h = 2.f * r / float(kNodes);
    const float a = value[std::size_t(i)], b = value[std::size_t(i) + 1];
    const float want = std::max(0.f, m - cdf[std::size_t(i)]) / h;  // a t + (b - a) t^2 / 2
    float s;
    if (std::fabs(b - a) < 1e-6f * std::max(a, b)) {
        s = a > 0.f ? want / a : 0.5f;
    } else {
        s = (-a + std::sqrt(std::max(0.f, a * a + 2.f * (b - a) * want))) / (b - a);
    }
    return -r + h * (float(i) + std::clamp(s, 0.f, 1.f));
}

float PixelFilter::margin() const {
    return std::max(0.f, std::max(radius_x(), radius_y()) - 0.5f);
}

float PixelFilter::eval(float dx, float dy) const {
    return axis_[0].eval(type_, dx) * axis_[1].eval(type_, dy);
}

Point2 PixelFilter::pixel_position(Point2 u) const {
    if (unit_box()) return u;
    return {0.5f + axis_[0].sample(type_, u.x), 0.5f + axis_[1].sample(type_, u.y)};
}

std::string PixelFilter::describe() const {
    char buf[96];
    if (type_ == FilterType::Gaussian)
        std::snprintf(buf, sizeof buf, "gaussian, radius %g x %g, sigma %g", radius_x(), radius_y(),
                      sigma_);
    else
        std::snprintf(buf, sizeof buf, "%s, radius %g x %g", filter_type_name(type_), radius_x(),
                      radius_y());
    return buf;
}

}  // namespace foton
