// pbrt-v4's portal environment light (environment.h's EnvLayer with EnvMapping::Portal): the
// rectified map around the portal's normal and the windows of directions through it.
#include <algorithm>
#include <cmath>

#include "engine/core/error.h"
#include "environment.h"

namespace foton {

bool EnvLayer::to_portal(const Vec3& wi, Point2& uv, float* dw_duv) const {
    const Vec3 l{dot(wi, ex), dot(wi, ey), dot(wi, ez)};
    if (!(l.z > 0.f)) return false;
    const float alpha = std::atan2(l.x, l.z), beta = std::atan2(l.y, l.z);
    uv = {std::clamp((alpha + 0.5f * kPi) * kInvPi, 0.f, 1.f),
          std::clamp((beta + 0.5f * kPi) * kInvPi, 0.f, 1.f)};
    // d omega = pi^2 (1 + x^2)(1 + y^2) / r^3 du dv for (x, y, 1) / r = (tan alpha, tan beta, 1) /
    // r.
    if (dw_duv) *dw_duv = kPi * kPi * (1.f - l.x * l.x) * (1.f - l.y * l.y) / l.z;
    return true;
}

Vec3 EnvLayer::from_portal(Point2 uv, float& dw_duv) const {
    const float x = std::tan(kPi * (uv.x - 0.5f)), y = std::tan(kPi * (uv.y - 0.5f));
    const Vec3 l = normalize(Vec3{x, y, 1.f});
    dw_duv = kPi * kPi * (1.f - l.x * l.x) * (1.f - l.y * l.y) / l.z;
    return ex * l.x + ey * l.y + ez * l.z;
}

bool EnvLayer::window_from(const Vec3& p, Window2& w) const {
    // Seen from p, the rectangle's opposite corners bound its rectified window.
    Point2 a, b;
    if (!to_portal(normalize(corners[0] - p), a) || !to_portal(normalize(corners[2] - p), b))
        return false;
    w = {std::min(a.x, b.x), std::min(a.y, b.y), std::max(a.x, b.x), std::max(a.y, b.y)};
    return true;
}

bool EnvLayer::crosses_portal(const Vec3& from, const Vec3& d) const {
    const float dn = dot(d, ez);
    if (dn == 0.f) return false;
    const float t = dot(corners[0] - from, ez) / dn;
    if (!(t > 0.f)) return false;
    const Vec3 q = from + d * t - corners[0];
    const float x = dot(q, ex), y = dot(q, ey);
    return x >= 0.f && x <= length(corners[3] - corners[0]) && y >= 0.f &&
           y <= length(corners[1] - corners[0]);
}

bool Environment::is_rectangle(const Vec3 c[4]) {
    // Opposite sides equal, adjacent ones perpendicular (so the corners lie in one plane).
    const Vec3 e01 = c[1] - c[0], e03 = c[3] - c[0];
    const float l01 = length(e01), l03 = length(e03);
    return l01 > 0.f && l03 > 0.f && length(c[2] - c[3] - e01) < 1e-3f * l01 &&
           length(c[2] - c[1] - e03) < 1e-3f * l03 && std::fabs(dot(e01, e03)) < 1e-3f * l01 * l03;
}

Environment Environment::portal(const TextureImage& map, const RGB& scale, const Vec3& up,
                                const Vec3& front, const Vec3 c[4]) {
    if (map.width != map.height)
        throw InputError(map.path, 0,
                         "a portal light's map must be a square equal-area image, not " +
                             std::to_string(map.width) + "x" + std::to_string(map.height));
    check_env_texels(map, scale);
    if (!is_rectangle(c))
        throw InputError(map.path, 0, "a portal must be a rectangle (4 corners in order round it)");
    const Vec3 e01 = c[1] - c[0], e03 = c[3] - c[0];
    const float l01 = length(e01), l03 = length(e03);
    EnvLayer l;
    l.mapping = EnvMapping::Portal;
    l.scale = scale;
    for (int i = 0; i < 4; ++i) l.corners[i] = c[i];
    l.ex = e03 / l03;
    l.ey = e01 / l01;
    l.ez = cross(l.ex, l.ey);
    // The equal-area map in its own frame, resampled (nearest texel) into the rectified one.
    EnvLayer src;
    src.mapping = EnvMapping::EqualArea;
    src.map = map;
    env_map_frame(up, front, src.ex, src.ey, src.ez);
    const int n = map.width;
    l.map.width = l.map.height = n;
    l.map.path = map.path;
    l.map.texels.resize(std::size_t(n) * std::size_t(n));
    std::vector<float> weights(l.map.texels.size());
    RGB sum{0.f};
    for (int row = 0; row < n; ++row)
        for (int col = 0; col < n; ++col) {
            const Point2 uv{(float(col) + 0.5f) / float(n), (float(row) + 0.5f) / float(n)};
            float dw_duv;
            const Vec3 wi = l.from_portal(uv, dw_duv);
            const RGB t = src.texel(src.to_map(wi));
            const std::size_t i = std::size_t(row) * std::size_t(n) + std::size_t(col);
            l.map.texels[i] = t;
            // Sampled by radiance per solid angle: the map's density carries d omega / d(u, v).
            weights[i] = std::max(0.f, t.luminance()) * dw_duv;
            sum += t * dw_duv;
        }
    l.window_dist = WindowedDistribution(weights, n, n);
    if (!(l.window_dist.integral(Window2{}) > 0.0))
        throw InputError(map.path, 0, "the portal light's map is black through its portal");
    l.integral = sum * scale * (1.f / (float(n) * float(n)));
    Environment e;
    e.layers_.push_back(std::move(l));
    e.finish();
    return e;
}

}  // namespace foton
