#include "sphere_histogram.h"

#include <algorithm>
#include <cmath>

namespace foton {

void SphereHistogram::clear() {
    p_.fill(0.f);
    row_.fill(0.f);
    count_ = 0;
}

int SphereHistogram::cell_of(const Vec3& d) {
    static_assert(kCols == 16, "the column search below cuts phi into 16 sectors");
    const int row = std::clamp(int((d.z + 1.f) * (0.5f * kRows)), 0, kRows - 1);
    // The sector of phi = atan2(y, x) by rotations and comparisons instead of atan2, which
    // is most of a lookup's cost (every guided vertex evaluates this two or three times).
    float x = d.x, y = d.y;
    int col = 0;
    if (y < 0.f) {  // by pi
        x = -x;
        y = -y;
        col = 8;
    }
    if (x <= 0.f) {  // by pi / 2
        const float t = x;
        x = y;
        y = -t;
        col += 4;
    }
    if (y > x) {  // by pi / 4
        constexpr float h = 0.70710678f;
        const float t = x;
        x = (t + y) * h;
        y = (y - t) * h;
        col += 2;
    }
    if (y > 0.41421356f * x) ++col;  // tan(pi / 8)
    return row * kCols + col;
}

void SphereHistogram::add(const Vec3& d, float w) {
    if (!(w > 0.f)) return;
    p_[std::size_t(cell_of(d))] += w;
    ++count_;
}

bool SphereHistogram::finish(float floor) {
    double total = 0.0;
    for (float w : p_) total += w;
    if (count_ == 0 || !(total > 0.0)) return false;
    const float add = float(floor * total / kCells);
    const float inv = float(1.0 / (total * (1.0 + floor)));
    for (int r = 0; r < kRows; ++r) {
        float sum = 0.f;
        for (int c = 0; c < kCols; ++c) {
            float& p = p_[std::size_t(r * kCols + c)];
            p = (p + add) * inv;
            sum += p;
        }
        row_[std::size_t(r)] = sum;
    }
    return true;
}

Vec3 SphereHistogram::sample(Point2 u, float& pdf) const {
    // Row by u.x, then the cell in the row by u.y, each stretched back to [0, 1) within the
    // choice (stratified u stay stratified).
    float x = u.x, acc = 0.f;
    int row = 0;
    for (; row < kRows - 1; ++row) {
        if (x < acc + row_[std::size_t(row)]) break;
        acc += row_[std::size_t(row)];
    }
    const float rw = row_[std::size_t(row)];
    const float fr = rw > 0.f ? std::clamp((x - acc) / rw, 0.f, 0x1.fffffep-1f) : 0.5f;
    const float* p = &p_[std::size_t(row * kCols)];
    float y = u.y * rw, acc_c = 0.f;
    int col = 0;
    for (; col < kCols - 1; ++col) {
        if (y < acc_c + p[col]) break;
        acc_c += p[col];
    }
    const float fc = p[col] > 0.f ? std::clamp((y - acc_c) / p[col], 0.f, 0x1.fffffep-1f) : 0.5f;
    const float z = -1.f + 2.f * (float(row) + fr) / kRows;
    const float phi = 2.f * kPi * (float(col) + fc) / kCols;
    const float s = std::sqrt(std::max(0.f, 1.f - z * z));
    const Vec3 d{s * std::cos(phi), s * std::sin(phi), z};
    pdf = this->pdf(d);  // the same cell as pdf(d) finds, even where rounding crosses an edge
    return d;
}

}  // namespace foton
