#include "direction_projection.h"

#include <algorithm>
#include <cmath>

#include "cube_bins.h"
#include "projection_map.h"
#include "scene.h"
#include "scene_outline.h"

namespace foton {

namespace {

// The solid angle of the face cell [u0, u1] x [v0, v1] (a rectangle on the plane at distance 1).
double cell_solid_angle(double u0, double u1, double v0, double v1) {
    auto f = [](double u, double v) { return std::atan2(u * v, std::sqrt(1.0 + u * u + v * v)); };
    return f(u1, v1) - f(u0, v1) - f(u1, v0) + f(u0, v0);
}

}  // namespace

void DirectionProjection::build(const Scene& scene, const Vec3& p, const Vec3& axis,
                                float cos_max) {
    const int n = kFaceRes;
    const float cell = 2.f / float(n);
    kept_.clear();
    cdf_.clear();
    omega_ = 0.f;
    const std::vector<Bounds3> boxes = scene_outline(scene, kVoxels, false);
    if (boxes.empty()) return;
    // Whether bin (f, i, j)'s cone of directions reaches into the spot's (always, for a point).
    auto in_cone = [&](int f, int i, int j) {
        if (cos_max <= -1.f) return true;
        const float u0 = -1.f + cell * float(i), v0 = -1.f + cell * float(j);
        const Vec3 c = normalize(face_direction(f, u0 + 0.5f * cell, v0 + 0.5f * cell));
        float cos_bin = 1.f;
        for (int k = 0; k < 4; ++k)
            cos_bin =
                std::min(cos_bin, dot(c, normalize(face_direction(f, u0 + (k & 1 ? cell : 0.f),
                                                                  v0 + (k & 2 ? cell : 0.f)))));
        const float to_axis = std::acos(std::clamp(dot(c, axis), -1.f, 1.f));
        return to_axis - std::acos(std::clamp(cos_bin, -1.f, 1.f)) <= std::acos(cos_max) + 1e-4f;
    };
    std::vector<uint8_t> mark(std::size_t(n) * std::size_t(n));
    std::vector<Point2> corners;
    std::size_t candidates = 0;  // bins in the cone, geometry or not
    for (int f = 0; f < 6; ++f) {
        const int a = f / 2;
        const float sign = f % 2 == 0 ? 1.f : -1.f;
        std::fill(mark.begin(), mark.end(), 0);
        for (const Bounds3& b : boxes) {
            // The box relative to the light: its depth range along the face's axis and its
            // two lateral ranges.
            const Vec3 lo = b.lo - p, hi = b.hi - p;
            float d0 = sign > 0.f ? lo[a] : -hi[a], d1 = sign > 0.f ? hi[a] : -lo[a];
            // A point is in the face's frustum only if its depth is at least its lateral
            // (Chebyshev) distance, which is at least the box's, L: the box's part at depth
            // below L is outside the face, so the box is clipped there (an axis-aligned box
            // still; its corners project to a convex hull).
            float lateral = 0.f;
            for (const int k : {(a + 1) % 3, (a + 2) % 3})
                lateral = std::max(lateral, lo[k] > 0.f ? lo[k] : hi[k] < 0.f ? -hi[k] : 0.f);
            d0 = std::max(d0, lateral);
            if (d1 < d0 || d1 <= 0.f) continue;  // no part of it in the face's frustum
            if (!(d0 > 0.f)) {  // it reaches the light's own position: every direction
                std::fill(mark.begin(), mark.end(), 1);
                break;
            }
            corners.clear();
            for (int k = 0; k < 8; ++k) {
                const float depth = k & 4 ? d1 : d0;
                const float l1 = k & 1 ? hi[(a + 1) % 3] : lo[(a + 1) % 3];
                const float l2 = k & 2 ? hi[(a + 2) % 3] : lo[(a + 2) % 3];
                corners.push_back({l1 / depth, l2 / depth});
            }
            mark_convex(convex_hull(corners), 1e-4f, n, 1.f, cell, mark);
        }
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                if (!in_cone(f, i, j)) continue;
                ++candidates;
                if (!mark[std::size_t(j) * std::size_t(n) + std::size_t(i)]) continue;
                const float u0 = -1.f + cell * float(i), v0 = -1.f + cell * float(j);
                const std::size_t bin =
                    (std::size_t(f) * std::size_t(n) + std::size_t(j)) * std::size_t(n) +
                    std::size_t(i);
                kept_.push_back(uint32_t(bin));
                omega_ += float(cell_solid_angle(u0, u0 + cell, v0, v0 + cell));
                cdf_.push_back(omega_);
            }
    }
    // Nothing pruned (a light inside closed geometry): no map; the light's own sampling is
    // exact and cheaper.
    if (kept_.size() == candidates) {
        kept_.clear();
        cdf_.clear();
        omega_ = 0.f;
    }
}

float DirectionProjection::density(std::size_t k, float u, float v) const {
    const float cell = 2.f / float(kFaceRes);
    const float omega_bin = cdf_[k] - (k > 0 ? cdf_[k - 1] : 0.f);
    const float r2 = 1.f + u * u + v * v;
    return omega_bin / omega_ / (cell * cell) * r2 * std::sqrt(r2);
}

Vec3 DirectionProjection::sample(Point2 u, float& pdf) const {
    const int n = kFaceRes;
    const float cell = 2.f / float(n);
    // The bin by u.x over the kept solid angle, u.x stretched back across it.
    const float x = u.x * omega_;
    const std::size_t k = std::min<std::size_t>(
        kept_.size() - 1,
        std::size_t(std::upper_bound(cdf_.begin(), cdf_.end(), x) - cdf_.begin()));
    const float lo = k > 0 ? cdf_[k - 1] : 0.f;
    const float ux = std::clamp((x - lo) / (cdf_[k] - lo), 0.f, 0x1.fffffep-1f);
    const uint32_t bin = kept_[k];
    const int f = int(bin / uint32_t(n * n)), j = int(bin / uint32_t(n) % uint32_t(n)),
              i = int(bin % uint32_t(n));
    const float fu = -1.f + cell * (float(i) + ux), fv = -1.f + cell * (float(j) + u.y);
    // The density from the bin drawn (pdf() finds the same bin but for a direction on its edge).
    pdf = density(k, fu, fv);
    return normalize(face_direction(f, fu, fv));
}

float DirectionProjection::pdf(const Vec3& d) const {
    if (kept_.empty()) return 0.f;
    const int n = kFaceRes;
    const CubeBin b = cube_bin(d, n);
    const auto at = std::lower_bound(kept_.begin(), kept_.end(), uint32_t(b.index));
    if (at == kept_.end() || *at != uint32_t(b.index)) return 0.f;
    return density(std::size_t(at - kept_.begin()), b.u, b.v);
}

}  // namespace foton
