#include "gather_guide.h"

#include <algorithm>
#include <cmath>

#include "engine/core/distribution.h"

namespace foton {

void GatherGuide::clear() {
    weight_.fill(0.f);
    photons_ = 0;
}

int GatherGuide::cell_of(const Vec3& wi, int& row, int& col) {
    const float u1 = std::max(0.f, 1.f - wi.z * wi.z);  // sin^2 theta
    float phi = std::atan2(wi.y, wi.x);
    if (phi < 0.f) phi += 2.f * kPi;
    row = std::min(kRes - 1, int(u1 * kRes));
    col = std::min(kRes - 1, int(phi * (kRes / (2.f * kPi))));
    return row * kRes + col;
}

void GatherGuide::add(const Vec3& wi, float w) {
    if (wi.z <= 0.f || !(w > 0.f)) return;
    int row, col;
    weight_[std::size_t(cell_of(wi, row, col))] += w;
    ++photons_;
}

bool GatherGuide::finish(float floor) {
    float total = 0.f;
    for (float w : weight_) total += w;
    if (photons_ == 0 || !(total > 0.f)) return false;
    const float add = floor * total / float(kRes * kRes);
    total *= 1.f + floor;
    for (float& w : weight_) w = (w + add) / total;
    row_cdf_[0] = 0.f;
    for (int r = 0; r < kRes; ++r) {
        float* c = &col_cdf_[std::size_t(r * (kRes + 1))];
        c[0] = 0.f;
        for (int j = 0; j < kRes; ++j) c[j + 1] = c[j] + weight_[std::size_t(r * kRes + j)];
        const float row = c[kRes];
        for (int j = 1; j <= kRes; ++j) c[j] /= row;
        c[kRes] = 1.f;
        row_cdf_[std::size_t(r + 1)] = row_cdf_[std::size_t(r)] + row;
    }
    for (int r = 1; r <= kRes; ++r) row_cdf_[std::size_t(r)] /= row_cdf_[kRes];
    row_cdf_[kRes] = 1.f;
    return true;
}

Vec3 GatherGuide::sample(Point2 u, float& pdf) const {
    float fr, fc;
    const int row = invert_cdf(row_cdf_.data(), kRes, u.x, fr);
    const int col = invert_cdf(&col_cdf_[std::size_t(row * (kRes + 1))], kRes, u.y, fc);
    const float u1 = (float(row) + fr) / kRes;  // sin^2 theta, uniform in the cell
    const float phi = 2.f * kPi * (float(col) + fc) / kRes;
    const float sin_t = std::sqrt(u1), cos_t = std::sqrt(std::max(0.f, 1.f - u1));
    const Vec3 wi{sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t};
    // The cosine-weighted square maps to the hemisphere with density cos / pi; a cell of
    // probability p covers 1 / kRes^2 of the square.
    pdf = weight_[std::size_t(row * kRes + col)] * float(kRes * kRes) * cos_t * kInvPi;
    return wi;
}

float GatherGuide::pdf(const Vec3& wi) const {
    if (wi.z <= 0.f) return 0.f;
    int row, col;
    return weight_[std::size_t(cell_of(wi, row, col))] * float(kRes * kRes) * wi.z * kInvPi;
}

}  // namespace foton
