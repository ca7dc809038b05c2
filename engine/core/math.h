#pragma once
// Small 3-vector math for the engine (the kernels use raw SoA floats instead).
#include <algorithm>
#include <cmath>
#include <limits>

namespace foton {

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 1.f / kPi;
inline constexpr float kInfinity = std::numeric_limits<float>::infinity();

struct Vec3 {
    float x = 0.f, y = 0.f, z = 0.f;
    constexpr Vec3() = default;
    constexpr Vec3(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
    float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    Vec3 operator-() const { return {-x, -y, -z}; }
    Vec3& operator+=(const Vec3& b) {
        x += b.x;
        y += b.y;
        z += b.z;
        return *this;
    }
    Vec3& operator-=(const Vec3& b) {
        x -= b.x;
        y -= b.y;
        z -= b.z;
        return *this;
    }
    Vec3& operator*=(float s) {
        x *= s;
        y *= s;
        z *= s;
        return *this;
    }
};

inline Vec3 operator+(const Vec3& a, const Vec3& b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline Vec3 operator-(const Vec3& a, const Vec3& b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline Vec3 operator*(const Vec3& a, float s) {
    return {a.x * s, a.y * s, a.z * s};
}
inline Vec3 operator*(float s, const Vec3& a) {
    return {a.x * s, a.y * s, a.z * s};
}
inline Vec3 operator/(const Vec3& a, float s) {
    return a * (1.f / s);
}
inline bool operator==(const Vec3& a, const Vec3& b) {
    return a.x == b.x && a.y == b.y && a.z == b.z;
}
inline float dot(const Vec3& a, const Vec3& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length_squared(const Vec3& a) {
    return dot(a, a);
}
inline float length(const Vec3& a) {
    return std::sqrt(dot(a, a));
}
inline Vec3 normalize(const Vec3& a) {
    return a / length(a);
}
inline Vec3 vmin(const Vec3& a, const Vec3& b) {
    return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
inline Vec3 vmax(const Vec3& a, const Vec3& b) {
    return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
inline float max_abs_component(const Vec3& a) {
    return std::max({std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)});
}
// Offset for rays leaving point p, found at distance t along a ray (0 for a sampled point):
// a few float ulps of the larger of its coordinates and that distance, so it scales with the
// scene and the distance.
inline float offset_epsilon(const Vec3& p, float t) {
    constexpr float kRelative = 2e-5f;
    return kRelative * (max_abs_component(p) + t);
}
inline bool is_finite(const Vec3& a) {
    return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}
inline Vec3 reflect(const Vec3& d, const Vec3& n) {
    return d - n * (2.f * dot(d, n));
}

// Any two unit vectors completing an orthonormal basis with n (Duff et al. 2017).
inline void orthonormal_basis(const Vec3& n, Vec3& s, Vec3& t) {
    const float sign = std::copysign(1.f, n.z);
    const float a = -1.f / (sign + n.z);
    const float b = n.x * n.y * a;
    s = {1.f + sign * n.x * n.x * a, sign * b, -sign * n.x};
    t = {b, sign + n.y * n.y * a, -n.y};
}

struct Bounds3 {
    Vec3 lo{kInfinity, kInfinity, kInfinity};
    Vec3 hi{-kInfinity, -kInfinity, -kInfinity};
    void extend(const Vec3& p) {
        lo = vmin(lo, p);
        hi = vmax(hi, p);
    }
    void extend(const Bounds3& b) {
        lo = vmin(lo, b.lo);
        hi = vmax(hi, b.hi);
    }
    bool empty() const { return lo.x > hi.x; }
    Vec3 diagonal() const { return hi - lo; }
    Vec3 center() const { return (lo + hi) * 0.5f; }
};

// A 3x4 affine transform (rotation/scale part + translation), row-major.
struct Affine {
    float m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
    Vec3 point(const Vec3& p) const {
        return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
                m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
                m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
    }
    Vec3 vector(const Vec3& v) const {
        return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
                m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
                m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
    }
    // Normals transform with the inverse transpose of the linear part.
    Vec3 normal(const Vec3& n) const;
    float determinant() const;
    // The inverse (the matrix must not be singular: check determinant() first).
    Affine inverse() const;
    static Affine translate(const Vec3& t);
    static Affine scale(const Vec3& s);
    static Affine rotate(const Vec3& axis, float degrees);
    // this applied after `first`.
    Affine operator*(const Affine& first) const;
    bool is_identity() const;
};

}  // namespace foton
