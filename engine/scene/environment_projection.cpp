#include "environment_projection.h"

#include <algorithm>
#include <cmath>

#include "cube_bins.h"
#include "engine/core/warp.h"
#include "scene.h"
#include "scene_outline.h"

namespace foton {

void EnvironmentProjection::build(const Scene& scene, const Vec3& center, float radius) {
    bins_.clear();
    center_ = center;
    radius_ = radius;
    const std::vector<Bounds3> boxes = scene_outline(scene, kVoxels, true);
    if (boxes.empty() || !(radius > 0.f)) return;
    const int n = kFaceRes;
    bins_.resize(std::size_t(6 * n * n));
    for (int f = 0; f < 6; ++f)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                Bin& b = bins_[(std::size_t(f) * std::size_t(n) + std::size_t(j)) * std::size_t(n) +
                               std::size_t(i)];
                const float step = 2.f / float(n);
                const float u0 = -1.f + step * float(i), v0 = -1.f + step * float(j);
                b.c = normalize(face_direction(f, u0 + 0.5f * step, v0 + 0.5f * step));
                const warp::Frame fr(b.c);
                b.s = fr.s;
                b.t = fr.t;
                // The bin's widest angle from c is at a corner (a cube cell is convex in the
                // face plane, and the angle grows with the distance from c's point there).
                float cos_min = 1.f;
                for (int k = 0; k < 4; ++k) {
                    const Vec3 corner = normalize(
                        face_direction(f, u0 + (k & 1 ? step : 0.f), v0 + (k & 2 ? step : 0.f)));
                    cos_min = std::min(cos_min, dot(corner, b.c));
                }
                const float tan_max = std::sqrt(std::max(0.f, 1.f - cos_min * cos_min)) / cos_min;
                // A small margin over the exact shift for rounding, as the directional map's.
                const float grow = radius * tan_max * 1.001f + 1e-4f * radius;
                b.map.build(boxes, b.s, b.t, center, radius * (1.f + tan_max) * 1.001f, grow,
                            kMapRes);
            }
}

std::size_t EnvironmentProjection::bin_of(const Vec3& wi) const {
    return cube_bin(wi, kFaceRes).index;
}

void EnvironmentProjection::sample(const Vec3& wi, Point2 u, Vec3& origin, float& pdf_pos) const {
    const Bin& b = bins_[bin_of(wi)];
    const Point2 q = b.map.sample(u);
    const Vec3 on_plane = center_ + b.s * q.x + b.t * q.y;
    // Upstream along wi past every point of the bounding sphere on the ray's line.
    const float back = (radius_ + length(on_plane - center_)) * 1.01f;
    origin = on_plane + wi * back;
    pdf_pos = this->pdf_pos(wi);
}

float EnvironmentProjection::pdf_pos(const Vec3& wi) const {
    const Bin& b = bins_[bin_of(wi)];
    return 1.f / (b.map.area() * std::fabs(dot(b.c, wi)));
}

bool EnvironmentProjection::covers(const Vec3& wi, const Vec3& p) const {
    const Bin& b = bins_[bin_of(wi)];
    // Where the line through p along wi crosses the bin's plane (through the centre, across c).
    const Vec3 d = p - center_;
    const Vec3 x = d - wi * (dot(d, b.c) / dot(wi, b.c));
    return b.map.kept({dot(x, b.s), dot(x, b.t)});
}

float EnvironmentProjection::kept_fraction() const {
    if (bins_.empty()) return 1.f;
    double sum = 0.0;
    for (const Bin& b : bins_) sum += double(b.map.area());
    return float(sum / double(bins_.size()) / (kPi * double(radius_) * double(radius_)));
}

}  // namespace foton
