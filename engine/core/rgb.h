#pragma once
// Linear RGB radiance / reflectance triple.
#include <algorithm>
#include <cmath>

namespace foton {

struct RGB {
    float r = 0.f, g = 0.f, b = 0.f;
    constexpr RGB() = default;
    constexpr RGB(float r_, float g_, float b_) : r(r_), g(g_), b(b_) {}
    explicit constexpr RGB(float v) : r(v), g(v), b(v) {}
    RGB& operator+=(const RGB& o) {
        r += o.r;
        g += o.g;
        b += o.b;
        return *this;
    }
    RGB& operator*=(const RGB& o) {
        r *= o.r;
        g *= o.g;
        b *= o.b;
        return *this;
    }
    RGB& operator*=(float s) {
        r *= s;
        g *= s;
        b *= s;
        return *this;
    }
    float max_component() const { return std::max({r, g, b}); }
    float luminance() const { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }
    bool is_black() const { return r == 0.f && g == 0.f && b == 0.f; }
    bool is_finite() const { return std::isfinite(r) && std::isfinite(g) && std::isfinite(b); }
};

inline RGB operator+(const RGB& a, const RGB& b) {
    return {a.r + b.r, a.g + b.g, a.b + b.b};
}
inline RGB operator-(const RGB& a, const RGB& b) {
    return {a.r - b.r, a.g - b.g, a.b - b.b};
}
inline RGB operator*(const RGB& a, const RGB& b) {
    return {a.r * b.r, a.g * b.g, a.b * b.b};
}
inline RGB operator*(const RGB& a, float s) {
    return {a.r * s, a.g * s, a.b * s};
}
inline RGB operator*(float s, const RGB& a) {
    return {a.r * s, a.g * s, a.b * s};
}
inline bool operator==(const RGB& a, const RGB& b) {
    return a.r == b.r && a.g == b.g && a.b == b.b;
}

}  // namespace foton
