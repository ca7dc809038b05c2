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
        case EnvMapping::Portal:
            return "portal";
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

void env_map_frame(const Vec3& up, const Vec3& front, Vec3& ex, Vec3& ey, Vec3& ez) {
    ez = normalize(up);
    ex = front - ez * dot(front, ez);
    if (!(length_squared(ex) > 1e-12f)) {
        Vec3 t;
        orthonormal_basis(ez, ex, t);
    }
    ex = normalize(ex);
    ey = cross(ez, ex);
}

void check_env_texels(const TextureImage& map, const RGB& scale) {
    // The brightest texel times the scale is what a ray can bring back (an HDR exponent of
    // 255 decodes to 1.7e38).
    RGB brightest{0.f};
    for (const RGB& t : map.texels) {
        if (!std::isfinite(t.r) || !std::isfinite(t.g) || !std::isfinite(t.b))
            throw InputError(map.path, 0, "the environment map holds NaN or infinite texels");
        brightest =
            RGB{std::max(brightest.r, t.r), std::max(brightest.g, t.g), std::max(brightest.b, t.b)};
    }
    if (const std::string why = emission_problem(brightest * scale); !why.empty())
        throw InputError(map.path, 0, "the brightest texel times the scale " + why);
}

Environment Environment::constant(const RGB& radiance) {
    Environment e;
    EnvLayer l;
    l.mapping = EnvMapping::Constant;
    l.scale = radiance;
    l.integral = radiance * (4.f * kPi);
    e.layers_.push_back(l);
    e.finish();
    return e;
}

Environment Environment::image(TextureImage map, EnvMapping mapping, const RGB& scale,
                               const Vec3& up, const Vec3& front) {
    EnvLayer l;
    l.mapping = mapping;
    l.scale = scale;
    l.map = std::move(map);
    const int w = l.map.width, h = l.map.height;
    if (mapping == EnvMapping::EqualArea && w != h)
        throw InputError(l.map.path, 0,
                         "an equal-area environment map must be square, not " + std::to_string(w) +
                             "x" + std::to_string(h));
    env_map_frame(up, front, l.ex, l.ey, l.ez);
    check_env_texels(l.map, scale);
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
            const RGB& t = l.map.texels[i];
            weights[i] = std::max(0.f, t.luminance()) * jac;
            row_sum += t;
        }
        sum += row_sum * jac;
    }
    try {
        l.dist = Distribution2D(weights, w, h);
    } catch (const std::invalid_argument&) {
        throw InputError(l.map.path, 0, "the environment map is black: it would light nothing");
    }
    // The solid angle of the square's unit area: 2 pi^2 (lat-long, with sin theta) or 4 pi.
    const float per_area = mapping == EnvMapping::LatLong ? 2.f * kPi * kPi : 4.f * kPi;
    l.integral = sum * l.scale * (per_area / (float(w) * float(h)));
    Environment e;
    e.layers_.push_back(std::move(l));
    e.finish();
    return e;
}

void Environment::add(const Environment& other) {
    layers_.insert(layers_.end(), other.layers_.begin(), other.layers_.end());
    finish();
}

bool Environment::has_portal() const {
    for (const EnvLayer& l : layers_)
        if (l.mapping == EnvMapping::Portal) return true;
    return false;
}

void Environment::finish() {
    integral_ = RGB{0.f};
    float total = 0.f;
    for (const EnvLayer& l : layers_) {
        integral_ += l.integral;
        total += std::max(l.integral.luminance(), 1e-12f);
    }
    for (EnvLayer& l : layers_) l.pick = std::max(l.integral.luminance(), 1e-12f) / total;
}

const EnvLayer& Environment::pick(Point2& u) const {
    float acc = 0.f;
    for (std::size_t i = 0; i + 1 < layers_.size(); ++i) {
        const EnvLayer& l = layers_[i];
        if (u.x < acc + l.pick) {
            u.x = std::min((u.x - acc) / l.pick, 0x1.fffffep-1f);
            return l;
        }
        acc += l.pick;
    }
    const EnvLayer& l = layers_.back();
    u.x = std::clamp((u.x - acc) / l.pick, 0.f, 0x1.fffffep-1f);
    return l;
}

Point2 EnvLayer::to_map(const Vec3& wi) const {
    const Vec3 l{dot(wi, ex), dot(wi, ey), dot(wi, ez)};
    if (mapping == EnvMapping::EqualArea) {
        const Point2 s = equal_area_sphere_to_square(l);
        return {s.x, s.y};
    }
    float phi = std::atan2(l.y, l.x);
    if (phi < 0.f) phi += 2.f * kPi;
    const float theta = std::acos(std::clamp(l.z, -1.f, 1.f));
    return {phi * (0.5f * kInvPi), theta * kInvPi};
}

Vec3 EnvLayer::from_map(Point2 uv) const {
    Vec3 l;
    if (mapping == EnvMapping::EqualArea) {
        l = equal_area_square_to_sphere(uv);
    } else {
        const float phi = 2.f * kPi * uv.x, theta = kPi * uv.y;
        const float st = std::sin(theta);
        l = {st * std::cos(phi), st * std::sin(phi), std::cos(theta)};
    }
    return ex * l.x + ey * l.y + ez * l.z;
}

RGB EnvLayer::texel(Point2 uv) const {
    const int w = map.width, h = map.height;
    const int col = std::clamp(int(uv.x * float(w)), 0, w - 1);
    const int row = std::clamp(int(uv.y * float(h)), 0, h - 1);
    return map.texels[std::size_t(row) * std::size_t(w) + std::size_t(col)] * scale;
}

namespace {

// A lat-long or equal-area layer's pdf of direction wi from its map density.
float map_pdf(const EnvLayer& l, const Vec3& wi) {
    const Point2 uv = l.to_map(wi);
    const float pdf_uv = l.dist.pdf(uv);
    if (l.mapping == EnvMapping::EqualArea) return pdf_uv / (4.f * kPi);
    const float st = std::sin(kPi * uv.y);
    return st > 0.f ? pdf_uv / (2.f * kPi * kPi * st) : 0.f;
}

// A layer's radiance from wi, seen from p (`windowed`) or along a ray from outside. A
// portal's window from p holds exactly the directions whose rays cross the rectangle, which
// the plane test finds without the window's arc tangents.
RGB layer_le(const EnvLayer& l, const Vec3& p, const Vec3& wi, bool windowed) {
    switch (l.mapping) {
        case EnvMapping::Constant:
            return l.scale;
        case EnvMapping::Portal: {
            Point2 uv;
            if (!l.crosses_portal(p, windowed ? wi : -wi) || !l.to_portal(wi, uv)) return RGB{0.f};
            return l.texel(uv);
        }
        default:
            return l.texel(l.to_map(wi));
    }
}

// A layer's direction for u (from p within a portal's window when `window` is given).
Vec3 layer_sample(const EnvLayer& l, const Window2* window, Point2 u, float& pdf) {
    pdf = 0.f;
    if (l.mapping == EnvMapping::Constant) {
        pdf = warp::kUniformSpherePdf;
        return warp::uniform_sphere(u);
    }
    if (l.mapping == EnvMapping::Portal) {
        Point2 uv;
        float pdf_uv, dw_duv;
        if (!l.window_dist.sample(u, window ? *window : Window2{}, uv, pdf_uv)) return Vec3{};
        const Vec3 wi = l.from_portal(uv, dw_duv);
        pdf = dw_duv > 0.f ? pdf_uv / dw_duv : 0.f;
        return wi;
    }
    float pdf_uv;
    const Point2 uv = l.dist.sample(u, pdf_uv);
    const Vec3 wi = l.from_map(uv);
    if (l.mapping == EnvMapping::EqualArea) {
        pdf = pdf_uv / (4.f * kPi);
    } else {
        const float st = std::sin(kPi * uv.y);
        pdf = st > 0.f ? pdf_uv / (2.f * kPi * kPi * st) : 0.f;
    }
    return wi;
}

float layer_pdf(const EnvLayer& l, const Window2* window, const Vec3& wi) {
    if (l.mapping == EnvMapping::Constant) return warp::kUniformSpherePdf;
    if (l.mapping != EnvMapping::Portal) return map_pdf(l, wi);
    Point2 uv;
    float dw_duv;
    if (!l.to_portal(wi, uv, &dw_duv) || !(dw_duv > 0.f)) return 0.f;
    return l.window_dist.pdf(uv, window ? *window : Window2{}) / dw_duv;
}

}  // namespace

RGB Environment::Le(const Vec3& p, const Vec3& wi) const {
    RGB sum{0.f};
    for (const EnvLayer& l : layers_) sum += layer_le(l, p, wi, true);
    return sum;
}

RGB Environment::Le_emitted(const Vec3& from, const Vec3& wi) const {
    RGB sum{0.f};
    for (const EnvLayer& l : layers_) sum += layer_le(l, from, wi, false);
    return sum;
}

Vec3 Environment::sample(const Vec3& p, Point2 u, float& pdf) const {
    if (uniform_) {
        const Vec3 wi = warp::uniform_sphere(u);
        pdf = warp::kUniformSpherePdf;
        return wi;
    }
    const EnvLayer& l = pick(u);
    Window2 w;
    if (l.mapping == EnvMapping::Portal && !l.window_from(p, w)) {
        pdf = 0.f;
        return Vec3{};
    }
    float own = 0.f;
    const Vec3 wi = layer_sample(l, &w, u, own);
    if (!(own > 0.f)) {
        pdf = 0.f;
        return wi;
    }
    // One layer: its own density (no second look at the window).
    pdf = layers_.size() == 1 ? own : this->pdf(p, wi);
    return wi;
}

float Environment::pdf(const Vec3& p, const Vec3& wi) const {
    if (uniform_) return warp::kUniformSpherePdf;
    float sum = 0.f;
    for (const EnvLayer& l : layers_) {
        Window2 w;
        if (l.mapping == EnvMapping::Portal && !l.window_from(p, w)) continue;
        sum += l.pick * layer_pdf(l, &w, wi);
    }
    return sum;
}

Vec3 Environment::sample_emission(Point2 u, float& pdf) const {
    if (uniform_) {
        pdf = warp::kUniformSpherePdf;
        return warp::uniform_sphere(u);
    }
    const EnvLayer& l = pick(u);
    float own = 0.f;
    const Vec3 wi = layer_sample(l, nullptr, u, own);
    pdf = !(own > 0.f) ? 0.f : layers_.size() == 1 ? own : pdf_emission(wi);
    return wi;
}

float Environment::pdf_emission(const Vec3& wi) const {
    if (uniform_) return warp::kUniformSpherePdf;
    float sum = 0.f;
    for (const EnvLayer& l : layers_) sum += l.pick * layer_pdf(l, nullptr, wi);
    return sum;
}

}  // namespace foton
