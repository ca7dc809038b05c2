#include "pixel_filter.h"

#include <cstdio>

#include "engine/core/math.h"

namespace foton {

namespace {

constexpr int kNodes = 256;  // Gaussian table intervals per axis

float gaussian_at(float x, float sigma) {
    return std::exp(-x * x / (2.f * sigma * sigma)) / (std::sqrt(2.f * kPi) * sigma);
}

// Mitchell and Netravali's cubic on [-2, 2] (their 1988 paper's piecewise form).
float mitchell_at(float x, float b, float c) {
    x = std::fabs(x);
    if (x > 2.f) return 0.f;
    if (x > 1.f)
        return ((-b - 6.f * c) * x * x * x + (6.f * b + 30.f * c) * x * x +
                (-12.f * b - 48.f * c) * x + (8.f * b + 24.f * c)) /
               6.f;
    return ((12.f - 9.f * b - 6.f * c) * x * x * x + (-18.f + 12.f * b + 6.f * c) * x * x +
            (6.f - 2.f * b)) /
           6.f;
}

float sinc(float x) {
    return std::fabs(x) < 1e-5f ? 1.f - kPi * kPi * x * x / 6.f : std::sin(kPi * x) / (kPi * x);
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
        case FilterType::Mitchell:
            return "mitchell";
        case FilterType::Lanczos:
            return "lanczos";
    }
    return "?";
}

bool parse_filter_type(const std::string& name, FilterType& t) {
    for (FilterType k : {FilterType::Box, FilterType::Triangle, FilterType::Gaussian,
                         FilterType::Mitchell, FilterType::Lanczos})
        if (name == filter_type_name(k)) {
            t = k;
            return true;
        }
    return false;
}

float default_filter_radius(FilterType t) {
    switch (t) {
        case FilterType::Box:
            return 0.5f;
        case FilterType::Gaussian:
            return 1.5f;
        case FilterType::Lanczos:
            return 4.f;
        default:
            return 2.f;
    }
}

PixelFilter PixelFilter::make(FilterType t, float rx, float ry, const FilterShape& shape) {
    switch (t) {
        case FilterType::Box:
            return box(rx, ry);
        case FilterType::Triangle:
            return triangle(rx, ry);
        case FilterType::Gaussian:
            return gaussian(rx, ry, shape.sigma);
        case FilterType::Mitchell:
            return mitchell(rx, ry, shape.b, shape.c);
        case FilterType::Lanczos:
            return lanczos(rx, ry, shape.tau);
    }
    return box(rx, ry);
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
    f.tabulate([sigma](float x, float r) {
        return std::max(0.f, gaussian_at(x, sigma) - gaussian_at(r, sigma));
    });
    return f;
}

PixelFilter PixelFilter::mitchell(float rx, float ry, float b, float c) {
    PixelFilter f = box(rx, ry);
    f.type_ = FilterType::Mitchell;
    f.sigma_ = b;
    f.c_ = c;
    f.tabulate([b, c](float x, float r) { return mitchell_at(2.f * x / r, b, c); });
    return f;
}

PixelFilter PixelFilter::lanczos(float rx, float ry, float tau) {
    PixelFilter f = box(rx, ry);
    f.type_ = FilterType::Lanczos;
    f.sigma_ = tau;
    f.tabulate([tau](float x, float) { return sinc(x) * sinc(x / tau); });
    return f;
}

template <class F>
void PixelFilter::tabulate(F&& fn) {
    for (Axis& a : axis_) {
        const float r = a.radius, h = 2.f * r / float(kNodes);
        a.value.resize(kNodes + 1);
        a.mag.resize(kNodes + 1);
        a.cdf.assign(kNodes + 1, 0.f);
        for (int i = 0; i <= kNodes; ++i) {
            const float v = i == 0 || i == kNodes ? 0.f : fn(-r + h * float(i), r);
            a.value[std::size_t(i)] = v;
            a.mag[std::size_t(i)] = std::fabs(v);
        }
        // Trapezoids: exact for the piecewise-linear functions the tables are.
        double mass = 0.0, signed_mass = 0.0;
        for (std::size_t i = 0; i < kNodes; ++i) {
            mass += 0.5 * double(h) * (double(a.mag[i]) + double(a.mag[i + 1]));
            signed_mass += 0.5 * double(h) * (double(a.value[i]) + double(a.value[i + 1]));
            a.cdf[i + 1] = float(mass);
        }
        a.integral = float(signed_mass);
        a.mag_integral = float(mass);
    }
}

float PixelFilter::Axis::lerp(const std::vector<float>& nodes, float pos) {
    const int i = std::clamp(int(pos), 0, kNodes - 1);
    const float f = pos - float(i);
    return nodes[std::size_t(i)] * (1.f - f) + nodes[std::size_t(i) + 1] * f;
}

float PixelFilter::Axis::eval(FilterType t, float x) const {
    const float ax = std::fabs(x);
    if (ax > radius) return 0.f;
    if (t == FilterType::Box) return 1.f;
    if (t == FilterType::Triangle) return radius - ax;
    return lerp(value, (x + radius) / (2.f * radius) * float(kNodes));
}

float PixelFilter::Axis::weight(float x) const {
    if (std::fabs(x) > radius) return 0.f;
    const float pos = (x + radius) / (2.f * radius) * float(kNodes);
    const float m = lerp(mag, pos);
    return m > 0.f ? lerp(value, pos) / m * (mag_integral / integral) : 0.f;
}

float PixelFilter::Axis::sample(FilterType t, float u) const {
    const float r = radius;
    if (t == FilterType::Box) return r * (2.f * u - 1.f);
    if (t == FilterType::Triangle)
        return u < 0.5f ? -r + r * std::sqrt(2.f * u) : r - r * std::sqrt(2.f * (1.f - u));
    // The interval holding mass u * mag_integral, then the linear piece of |f| inverted in it.
    const float m = u * mag_integral;
    const auto it = std::upper_bound(cdf.begin(), cdf.end(), m);
    const int i = std::clamp(int(it - cdf.begin()) - 1, 0, kNodes - 1);
    const float h = 2.f * r / float(kNodes);
    const float a = mag[std::size_t(i)], b = mag[std::size_t(i) + 1];
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

float PixelFilter::sample_weight(Point2 p) const {
    if (!negative_lobes()) return 1.f;
    return axis_[0].weight(p.x - 0.5f) * axis_[1].weight(p.y - 0.5f);
}

std::string PixelFilter::describe() const {
    char buf[96];
    if (type_ == FilterType::Gaussian)
        std::snprintf(buf, sizeof buf, "gaussian, radius %g x %g, sigma %g", radius_x(), radius_y(),
                      sigma_);
    else if (type_ == FilterType::Mitchell)
        std::snprintf(buf, sizeof buf, "mitchell, radius %g x %g, b %g, c %g", radius_x(),
                      radius_y(), sigma_, c_);
    else if (type_ == FilterType::Lanczos)
        std::snprintf(buf, sizeof buf, "lanczos, radius %g x %g, tau %g", radius_x(), radius_y(),
                      sigma_);
    else
        std::snprintf(buf, sizeof buf, "%s, radius %g x %g", filter_type_name(type_), radius_x(),
                      radius_y());
    return buf;
}

}  // namespace foton
