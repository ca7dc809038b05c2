#include "ppm_error_bound.h"

#include <algorithm>
#include <cmath>

#include <boost/math/distributions/students_t.hpp>

namespace foton {

namespace {

float channel(const RGB& c, int k) {
    return k == 0 ? c.r : k == 1 ? c.g : c.b;
}

}  // namespace

PpmErrorBound::PpmErrorBound(std::size_t pixels, float confidence)
    : sums_(pixels), confidence_(confidence) {}

void PpmErrorBound::record(std::size_t pixel, const RGB& estimate, const RGB& bias) {
    Sums& s = sums_[pixel];
    for (int k = 0; k < 3; ++k) {
        const double b = channel(bias, k), x = double(channel(estimate, k)) - b;
        s.x[k] += x;
        s.xx[k] += x * x;
        s.b[k] += b;
    }
}

double PpmErrorBound::t_factor(uint32_t passes) const {
    if (passes < 2) return 0.0;
    const boost::math::students_t dist(double(passes - 1));
    return boost::math::quantile(dist, 0.5 * (1.0 + double(confidence_)));
}

RGB PpmErrorBound::bias(std::size_t pixel, uint32_t passes) const {
    if (passes == 0) return {};
    const Sums& s = sums_[pixel];
    const double n = passes;
    return RGB(float(s.b[0] / n), float(s.b[1] / n), float(s.b[2] / n));
}

RGB PpmErrorBound::bound(std::size_t pixel, uint32_t passes) const {
    return bound(pixel, passes, t_factor(passes));
}

RGB PpmErrorBound::bound(std::size_t pixel, uint32_t passes, double t) const {
    if (passes < 2) return {};
    const Sums& s = sums_[pixel];
    const double n = passes;
    float out[3];
    for (int k = 0; k < 3; ++k) {
        // sum_j (X_j - mean)^2 = sum X^2 - (sum X)^2 / n, never below 0 in exact arithmetic.
        const double spread = std::max(0.0, s.xx[k] - s.x[k] * s.x[k] / n);
        const double variance_sum = spread * n / (n - 1.0);
        out[k] = float(std::fabs(s.b[k] / n) + t * std::sqrt(variance_sum) / n);
    }
    return {out[0], out[1], out[2]};
}

bool PpmErrorBound::converged(uint32_t passes, float relative, const std::vector<RGB>& image,
                              const Cluster& cluster, const PixelOwners& owner, double& mean_bound,
                              double& mean_value) const {
    mean_bound = mean_value = 0.0;
    if (image.empty()) return false;
    // Each rank's owned pixels' scalar bounds; rank 0 collects them in pixel order.
    std::vector<float> scalar(image.size(), 0.f);
    const double t = t_factor(passes);  // once: a quantile costs microseconds
    for (std::size_t p = 0; p < image.size(); ++p)
        if (owner[p] == cluster.rank()) scalar[p] = bound(p, passes, t).luminance();
    gather_to_root(cluster, owner, scalar);
    if (!cluster.root()) return false;
    for (std::size_t p = 0; p < image.size(); ++p) {
        mean_bound += scalar[p];
        mean_value += image[p].luminance();
    }
    mean_bound /= double(image.size());
    mean_value /= double(image.size());
    return passes >= kMinPasses && mean_bound <= double(relative) * mean_value;
}

}  // namespace foton
