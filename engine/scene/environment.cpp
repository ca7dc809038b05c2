#include "environment.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/core/error.h"
#include "engine/core/warp.h"
#include "light.h"

namespace foton {

const char* env_mapping_name(EnvMapping m) {
    switch (m) {
        case EnvMapping::Constant:
            return "constant";
        case EnvMapping::LatLong:
            return "latlong";
        case EnvMapping::EqualArea:
            return "equalarea";
    }
    return "?";
}

Vec3 equal_area_square_to_sphere(Point2 p) {
    const float u = 2.f * p.x - 1.f, v = 2.f * p.y - 1.f;
    const float up = std::fabs(u), vp = std::fabs(v);
    const float signed_distance = 1.f - (up + vp);
    const float d = std::fabs(signed_distance);
    const float r = 1.f - d;
    const float phi = (r == 0.f ? 1.f : (vp - up) / r + 1.f) * (0.25f * kPi);
    const float z = std::copysign(1.f - r * r, signed_distance);
    const float cos_phi = std::copysign(std::cos(phi), u);
    const float sin_phi = std::copysign(std::sin(phi), v);
    const float k = r * std::sqrt(std::max(0.f, 2.f - r * r));
    return {cos_phi * k, sin_phi * k, z};
}

Point2 equal_area_sphere_to_square(const Vec3& d) {
    const float x = std::fabs(d.x), y = std::fabs(d.y), z = std::fabs(d.z);
    const float r = std::sqrt(std::max(0.f, 1.f - z));
    const float a = std::max(x, y);
    const float b = a == 0.f ? 0.f : std::min(x, y) / a;
    float phi = std::atan(b) * (2.f / kPi);
    if (x < y) phi = 1.f - phi;
    float v = phi * r;
    float u = r - v;
    if (d.z < 0.f) {
        std::swap(u, v);
        u = 1.f - u;
        v = 1.f - v;
    }
    u = std::copysign(u, d.x);
    v = std::copysign(v, d.y);
    return {0.5f * (u + 1.f), 0.5f * (v + 1.f)};
}

Environment Environment::constant(const RGB& radiance) {
    Environment e;
    e.mapping_ = EnvMapping::Constant;
    e.scale_ = radiance;
    e.integral_ = radiance * (4.f * kPi);
    return e;
}

Environment Environment::image(TextureImage map, EnvMapping mapping, const RGB& scale,
                               const Vec3& up, const Vec3& front) {
    Environment e;
    e.mapping_ = mapping;
    e.scale_ = scale;
    e.map_ = std::move(map);
    const int w = e.map_.width, h = e.map_.height;
    if (mapping == EnvMapping::EqualArea && w != h)
        throw InputError(e.map_.path, 0,
                         "an equal-area environment map must be square, not " + std::to_string(w) +
                             "x" + std::to_string(h));
    e.ez_ = normalize(up);
    e.ex_ = front - e.ez_ * dot(front, e.ez_);
    if (!(length_squared(e.ex_) > 1e-12f)) {
        Vec3 t;
        orthonormal_basis(e.ez_, e.ex_, t);
    }
    e.ex_ = normalize(e.ex_);
    e.ey_ = cross(e.ez_, e.ex_);
    // Texel weights: luminance times the solid angle a texel covers per unit of map area
    // (sin theta for lat-long at the row's centre; constant for the equal-area square).
    std::vector<float> weights(std::size_t(w) * std::size_t(h));
    RGB sum{0.f};
    for (int row = 0; row < h; ++row) {
        const float jac =
            mapping == EnvMapping::LatLong ? std::sin(kPi * (float(row) + 0.5f) / float(h)) : 1.f;
        RGB row_sum{0.f};
        for (int col = 0; col < w; ++col) {
            const std::size_t i = std::size_t(row) * std::size_t(w) + std::size_t(col);
            const RGB& t = e.map_.texels[i];
            weights[i] = std::max(0.f, t.luminance()) * jac;
            row_sum += t;
        }
        sum += row_sum * jac;
    }
    // The brightest texel times the scale is what a ray can bring back (an HDR exponent of
    // 255 decodes to 1.7e38).
    RGB brightest{0.f};
    for (const RGB& t : e.map_.texels) {
        if (!std::isfinite(t.r) || !std::isfinite(t.g) || !std::isfinite(t.b))
            throw InputError(e.map_.path, 0, "the environment map holds NaN or infinite texels");
        brightest =
            RGB{std::max(brightest.r, t.r), std::max(brightest.g, t.g), std::max(brightest.b, t.b)};
    }
    if (const std::string why = emission_problem(brightest * scale); !why.empty())
        throw InputError(e.map_.path, 0, "the brightest texel times the scale " + why);
    try {
        e.dist_ = Distribution2D(weights, w, h);
    } catch (const std::invalid_argument&) {
        throw InputError(e.map_.path, 0, "the environment map is black: it would light nothing");
    }
    // The solid angle of the square's unit area: 2 pi^2 (lat-long, with sin theta) or 4 pi.
    const float per_area = mapping == EnvMapping::LatLong ? 2.f * kPi * kPi : 4.f * kPi;
    e.integral_ = sum * e.scale_ * (per_area / (float(w) * float(h)));
    return e;
}

Point2 Environment::to_map(const Vec3& wi) const {
    const Vec3 l{dot(wi, ex_), dot(wi, ey_), dot(wi, ez_)};
    if (mapping_ == EnvMapping::EqualArea) {
        const Point2 s = equal_area_sphere_to_square(l);
        return {s.x, s.y};
    }
    float phi = std::atan2(l.y, l.x);
    if (phi < 0.f) phi += 2.f * kPi;
    const float theta = std::acos(std::clamp(l.z, -1.f, 1.f));
    return {phi * (0.5f * kInvPi), theta * kInvPi};
}

Vec3 Environment::from_map(Point2 uv) const {
    Vec3 l;
    if (mapping_ == EnvMapping::EqualArea) {
        l = equal_area_square_to_sphere(uv);
    } else {
        const float phi = 2.f * kPi * uv.x, theta = kPi * uv.y;
        const float st = std::sin(theta);
        l = {st * std::cos(phi), st * std::sin(phi), std::cos(theta)};
    }
    return ex_ * l.x + ey_ * l.y + ez_ * l.z;
}

RGB Environment::Le(const Vec3& wi) const {
    if (mapping_ == EnvMapping::Constant) return scale_;
    const Point2 uv = to_map(wi);
    const int w = map_.width, h = map_.height;
    const int col = std::clamp(int(uv.x * float(w)), 0, w - 1);
    const int row = std::clamp(int(uv.y * float(h)), 0, h - 1);
    return map_.texels[std::size_t(row) * std::size_t(w) + std::size_t(col)] * scale_;
}

Vec3 Environment::sample(Point2 u, float& pdf) const {
    if (mapping_ == EnvMapping::Constant || uniform_) {
        pdf = warp::kUniformSpherePdf;
        return warp::uniform_sphere(u);
    }
    float pdf_uv;
    const Point2 uv = dist_.sample(u, pdf_uv);
    const Vec3 wi = from_map(uv);
    if (mapping_ == EnvMapping::EqualArea) {
        pdf = pdf_uv / (4.f * kPi);
    } else {
        const float st = std::sin(kPi * uv.y);
        pdf = st > 0.f ? pdf_uv / (2.f * kPi * kPi * st) : 0.f;
    }
    return wi;
}

float Environment::pdf(const Vec3& wi) const {
    if (mapping_ == EnvMapping::Constant || uniform_) return warp::kUniformSpherePdf;
    const Point2 uv = to_map(wi);
    const float pdf_uv = dist_.pdf(uv);
    if (mapping_ == EnvMapping::EqualArea) return pdf_uv / (4.f * kPi);
    const float st = std::sin(kPi * uv.y);
    return st > 0.f ? pdf_uv / (2.f * kPi * kPi * st) : 0.f;
}

}  // namespace foton
