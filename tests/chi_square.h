#pragma once
// Chi-square goodness-of-fit test of a direction sampler against its pdf, as pbrt and
// Mitsuba test theirs: directions are binned on a (theta, phi) grid in a frame around `axis`
// (put the axis on a sharp lobe's peak so its profile spans several theta bins), the
// expected count of each bin is the pdf integrated over the bin by a fine midpoint rule (with
// the sin(theta) Jacobian), bins with small expectations are pooled, and the statistic's
// p-value decides. A sampler that fails (returns false) simply adds no sample:
// its pdf must integrate to the success probability.
#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "engine/core/math.h"
#include "engine/core/warp.h"

namespace foton::test {

// Regularised upper incomplete gamma Q(a, x) (series below a + 1, continued fraction above).
inline double gamma_q(double a, double x) {
    if (x <= 0.0) return 1.0;
    const double gln = std::lgamma(a);
    if (x < a + 1.0) {
        double sum = 1.0 / a, term = sum, ap = a;
        for (int i = 0; i < 10000; ++i) {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if (std::fabs(term) < std::fabs(sum) * 1e-15) break;
        }
        return 1.0 - sum * std::exp(-x + a * std::log(x) - gln);
    }
    double b = x + 1.0 - a, c = 1e300, d = 1.0 / b, h = d;
    for (int i = 1; i < 10000; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::fabs(d) < 1e-300) d = 1e-300;
        c = b + an / c;
        if (std::fabs(c) < 1e-300) c = 1e-300;
        d = 1.0 / d;
        const double del = d * c;
        h *= del;
        if (std::fabs(del - 1.0) < 1e-15) break;
    }
    return std::exp(-x + a * std::log(x) - gln) * h;
}

struct ChiSquareResult {
    double statistic = 0.0;
    int dof = 0;
    double p_value = 1.0;
    double expected_total = 0.0;  // integral of the pdf over the domain (success rate)
    double observed_total = 0.0;
    std::string summary() const {
        return "chi2 " + std::to_string(statistic) + " dof " + std::to_string(dof) + " p " +
               std::to_string(p_value) + " pdf mass " + std::to_string(expected_total) +
               " observed " + std::to_string(observed_total);
    }
};

struct ChiSquareSetup {
    Vec3 axis{0, 0, 1};
    float theta_max = kPi;  // bins cover theta in [0, theta_max] about the axis
    int theta_res = 30, phi_res = 40;
    int samples = 200000;
    int quad = 16;  // midpoint rule points per bin and dimension
};

// sample(i, wi) draws the i-th direction; pdf(wi) is its solid-angle density.
inline ChiSquareResult chi_square(const ChiSquareSetup& s,
                                  const std::function<bool(int, Vec3&)>& sample,
                                  const std::function<double(const Vec3&)>& pdf) {
    const warp::Frame fr(normalize(s.axis));
    const int bins = s.theta_res * s.phi_res;
    std::vector<double> observed(std::size_t(bins), 0.0), expected(std::size_t(bins), 0.0);
    const double dt = double(s.theta_max) / s.theta_res, dphi = 2.0 * kPi / s.phi_res;
    auto bin_of = [&](const Vec3& w) -> int {
        const Vec3 l = fr.to_local(w);
        const double theta = std::acos(std::clamp(double(l.z), -1.0, 1.0));
        if (theta > s.theta_max) return -1;
        double phi = std::atan2(double(l.y), double(l.x));
        if (phi < 0) phi += 2.0 * kPi;
        const int iz = std::min(s.theta_res - 1, int(theta / dt));
        const int ip = std::min(s.phi_res - 1, int(phi / dphi));
        return iz * s.phi_res + ip;
    };
    ChiSquareResult r;
    double outside = 0.0;
    for (int i = 0; i < s.samples; ++i) {
        Vec3 w;
        if (!sample(i, w)) continue;
        const int b = bin_of(w);
        if (b < 0)
            outside += 1.0;
        else
            observed[std::size_t(b)] += 1.0;
        r.observed_total += 1.0;
    }
    for (int iz = 0; iz < s.theta_res; ++iz)
        for (int ip = 0; ip < s.phi_res; ++ip) {
            double sum = 0.0;
            for (int a = 0; a < s.quad; ++a)
                for (int c = 0; c < s.quad; ++c) {
                    const double theta = (iz + (a + 0.5) / s.quad) * dt;
                    const double phi = (ip + (c + 0.5) / s.quad) * dphi;
                    const double st = std::sin(theta);
                    const Vec3 l{float(st * std::cos(phi)), float(st * std::sin(phi)),
                                 float(std::cos(theta))};
                    sum += pdf(fr.to_world(l)) * st;
                }
            const double e = sum / (s.quad * s.quad) * dt * dphi * s.samples;
            expected[std::size_t(iz * s.phi_res + ip)] = e;
            r.expected_total += e;
        }
    r.expected_total /= s.samples;
    r.observed_total /= s.samples;
    // Pool bins expecting fewer than 5 samples (sorted by expectation) into one.
    std::vector<int> order(static_cast<std::size_t>(bins));
    for (int i = 0; i < bins; ++i) order[std::size_t(i)] = i;
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return expected[std::size_t(a)] < expected[std::size_t(b)]; });
    double pool_e = 0.0, pool_o = outside;
    int cells = 0;
    for (int i : order) {
        const double e = expected[std::size_t(i)], o = observed[std::size_t(i)];
        if (e == 0.0) {
            // Bins the quadrature sees no density in (or that straddle the horizon) go to the
            // pool, where samples the pdf does not account for still count against it.
            pool_o += o;
            continue;
        }
        if (e < 5.0 || (pool_e > 0.0 && pool_e < 5.0)) {
            pool_e += e;
            pool_o += o;
            continue;
        }
        r.statistic += (o - e) * (o - e) / e;
        ++cells;
    }
    if (pool_e > 0.0) {
        r.statistic += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
        ++cells;
    }
    r.dof = std::max(1, cells - 1);
    r.p_value = gamma_q(0.5 * r.dof, 0.5 * r.statistic);
    return r;
}

}  // namespace foton::test
