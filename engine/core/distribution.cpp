#include "distribution.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace foton {

int invert_cdf(const float* cdf, int n, float u, float& within) {
    int i = int(std::upper_bound(cdf + 1, cdf + n, u) - (cdf + 1));
    i = std::min(i, n - 1);
    while (i > 0 && cdf[i + 1] - cdf[i] <= 0.f) --i;
    const float width = cdf[i + 1] - cdf[i];
    within = width > 0.f ? std::clamp((u - cdf[i]) / width, 0.f, 0x1.fffffep-1f) : 0.5f;
    return i;
}

Distribution2D::Distribution2D(const std::vector<float>& weights, int nu, int nv)
    : nu_(nu), nv_(nv) {
    if (nu <= 0 || nv <= 0 || weights.size() != std::size_t(nu) * std::size_t(nv))
        throw std::invalid_argument("Distribution2D: weights do not match the size");
    // Sums in double: a 4k x 2k map has 8M cells, beyond float's exact running sums.
    std::vector<double> rows(std::size_t(nv), 0.0);
    double total = 0.0;
    for (int r = 0; r < nv; ++r) {
        for (int c = 0; c < nu; ++c) {
            const float w = weights[std::size_t(r) * std::size_t(nu) + std::size_t(c)];
            if (!(w >= 0.f) || !std::isfinite(w))
                throw std::invalid_argument("Distribution2D: a weight is negative or not finite");
            rows[std::size_t(r)] += double(w);
        }
        total += rows[std::size_t(r)];
    }
    if (!(total > 0.0)) throw std::invalid_argument("Distribution2D: every weight is zero");
    integral_ = total / (double(nu) * double(nv));
    density_.resize(weights.size());
    for (std::size_t i = 0; i < weights.size(); ++i)
        density_[i] = float(double(weights[i]) / integral_);
    row_cdf_.assign(std::size_t(nv) + 1, 0.f);
    cell_cdf_.assign(std::size_t(nv) * std::size_t(nu + 1), 0.f);
    double acc_rows = 0.0;
    for (int r = 0; r < nv; ++r) {
        float* cdf = &cell_cdf_[std::size_t(r) * std::size_t(nu + 1)];
        const double row = rows[std::size_t(r)];
        double acc = 0.0;
        for (int c = 0; c < nu; ++c) {
            acc += double(weights[std::size_t(r) * std::size_t(nu) + std::size_t(c)]);
            // An empty row is never chosen; give it a uniform CDF all the same.
            cdf[c + 1] = row > 0.0 ? float(acc / row) : float(c + 1) / float(nu);
        }
        cdf[nu] = 1.f;
        acc_rows += row;
        row_cdf_[std::size_t(r) + 1] = float(acc_rows / total);
    }
    row_cdf_[std::size_t(nv)] = 1.f;
}

Point2 Distribution2D::sample(Point2 u, float& pdf) const {
    float fr, fc;
    const int r = invert_cdf(row_cdf_.data(), nv_, u.x, fr);
    const int c = invert_cdf(&cell_cdf_[std::size_t(r) * std::size_t(nu_ + 1)], nu_, u.y, fc);
    pdf = density_[std::size_t(r) * std::size_t(nu_) + std::size_t(c)];
    return {(float(c) + fc) / float(nu_), (float(r) + fr) / float(nv_)};
}

float Distribution2D::pdf(Point2 p) const {
    const int c = std::clamp(int(p.x * float(nu_)), 0, nu_ - 1);
    const int r = std::clamp(int(p.y * float(nv_)), 0, nv_ - 1);
    return density_[std::size_t(r) * std::size_t(nu_) + std::size_t(c)];
}

}  // namespace foton
