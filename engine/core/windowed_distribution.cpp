#include "windowed_distribution.h"

#include <algorithm>
#include <cmath>

namespace foton {

WindowedDistribution::WindowedDistribution(const std::vector<float>& weights, int nu, int nv)
    : nu_(nu), nv_(nv), f_(weights) {
    const double cell = 1.0 / (double(nu) * double(nv));
    sat_.assign(std::size_t(nu + 1) * std::size_t(nv + 1), 0.0);
    auto at = [&](int x, int y) -> double& {
        return sat_[std::size_t(y) * std::size_t(nu + 1) + std::size_t(x)];
    };
    row_prefix_.assign(std::size_t(nu + 1) * std::size_t(nv), 0.0);
    for (int y = 0; y < nv; ++y)
        for (int x = 0; x < nu; ++x)
            row_prefix_[std::size_t(y) * std::size_t(nu + 1) + std::size_t(x + 1)] =
                row_prefix_[std::size_t(y) * std::size_t(nu + 1) + std::size_t(x)] +
                double(f_[std::size_t(y) * std::size_t(nu) + std::size_t(x)]);
    for (int y = 0; y < nv; ++y)
        for (int x = 0; x < nu; ++x)
            at(x + 1, y + 1) = at(x, y + 1) + at(x + 1, y) - at(x, y) +
                               double(f_[std::size_t(y) * std::size_t(nu) + std::size_t(x)]) * cell;
}

double WindowedDistribution::sat_at(double x, double y) const {
    // Bilinear between the corner sums: exact for a function constant on each cell.
    const double fx = std::clamp(x, 0.0, 1.0) * nu_, fy = std::clamp(y, 0.0, 1.0) * nv_;
    const int x0 = std::min(int(fx), nu_ - 1), y0 = std::min(int(fy), nv_ - 1);
    const double dx = fx - x0, dy = fy - y0;
    auto at = [&](int xi, int yi) {
        return sat_[std::size_t(yi) * std::size_t(nu_ + 1) + std::size_t(xi)];
    };
    return (1 - dx) * (1 - dy) * at(x0, y0) + dx * (1 - dy) * at(x0 + 1, y0) +
           (1 - dx) * dy * at(x0, y0 + 1) + dx * dy * at(x0 + 1, y0 + 1);
}

double WindowedDistribution::integral(const Window2& w) const {
    return sat_at(w.u1, w.v1) - sat_at(w.u0, w.v1) - sat_at(w.u1, w.v0) + sat_at(w.u0, w.v0);
}

float WindowedDistribution::value(Point2 p) const {
    const int x = std::clamp(int(p.x * float(nu_)), 0, nu_ - 1);
    const int y = std::clamp(int(p.y * float(nv_)), 0, nv_ - 1);
    return f_[std::size_t(y) * std::size_t(nu_) + std::size_t(x)];
}

float WindowedDistribution::pdf(Point2 p, const Window2& w) const {
    if (!w.contains(p)) return 0.f;
    const double total = integral(w);
    return total > 0.0 ? float(double(value(p)) / total) : 0.f;
}

bool WindowedDistribution::sample(Point2 u, const Window2& w, Point2& p, float& pdf) const {
    const double total = integral(w);
    if (!(total > 0.0)) return false;
    // v: the share of the window's integral below it is u.x (the integral is monotone in v).
    auto below = [&](double v) {
        return sat_at(w.u1, v) - sat_at(w.u0, v) - sat_at(w.u1, w.v0) + sat_at(w.u0, w.v0);
    };
    // The row boundaries bracket the target (binary search over them); within a row the
    // function does not change along v, so v is linear in the integral there.
    const double target_v = double(u.x) * total;
    auto boundary = [&](int r) { return std::clamp(double(r) / nv_, double(w.v0), double(w.v1)); };
    int lo = std::min(int(w.v0 * nv_), nv_ - 1), hi = std::min(int(std::ceil(w.v1 * nv_)), nv_);
    while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        (below(boundary(mid)) <= target_v ? lo : hi) = mid;
    }
    const double va = boundary(lo), vb = boundary(lo + 1);
    const double ia = below(va), ib = below(vb);
    const double v = ib > ia ? va + (target_v - ia) / (ib - ia) * (vb - va) : 0.5 * (va + vb);
    // u within the window, along the row at v (constant per cell): its running sums inverted.
    const int row = std::clamp(int(v * nv_), 0, nv_ - 1);
    const double* prefix = &row_prefix_[std::size_t(row) * std::size_t(nu_ + 1)];
    const float* f = &f_[std::size_t(row) * std::size_t(nu_)];
    auto running = [&](double x) {  // the row's integral from 0 to x, in cell units
        const double fx = std::clamp(x, 0.0, 1.0) * nu_;
        const int c = std::min(int(fx), nu_ - 1);
        return prefix[c] + double(f[c]) * (fx - c);
    };
    const double r0 = running(w.u0), r1 = running(w.u1);
    if (!(r1 > r0)) return false;
    const double target = r0 + double(u.y) * (r1 - r0);
    // The cell whose running sums bracket the target, then the point within it.
    const int first = std::min(int(w.u0 * nu_), nu_ - 1);
    int c = int(std::upper_bound(prefix + first, prefix + nu_ + 1, target) - prefix) - 1;
    c = std::clamp(c, first, nu_ - 1);
    while (c < nu_ - 1 && f[c] == 0.f) ++c;
    const double within = f[c] > 0.f ? (target - prefix[c]) / double(f[c]) : 0.0;
    const double x = (c + std::clamp(within, 0.0, 1.0)) / nu_;
    p = {float(std::clamp(x, double(w.u0), double(w.u1))), float(v)};
    pdf = float(double(value(p)) / total);
    return pdf > 0.f;
}

}  // namespace foton
