#include "catmull_rom.h"

#include <algorithm>
#include <cmath>

namespace foton {

namespace {

// The interval [nodes[i], nodes[i+1]] holding x (x within the nodes).
std::size_t interval_of(std::span<const float> nodes, float x) {
    const auto it = std::upper_bound(nodes.begin(), nodes.end(), x);
    const std::size_t i = std::size_t(it - nodes.begin());
    return std::min(i == 0 ? 0 : i - 1, nodes.size() - 2);
}

// The end slopes (per unit t) of interval i of the spline through f (f(k): the k-th value).
template <class F>
void end_slopes(std::span<const float> x, std::size_t i, F&& f, float& d0, float& d1) {
    const std::size_t n = x.size();
    const float w = x[i + 1] - x[i];
    d0 = i > 0 ? w * (f(i + 1) - f(i - 1)) / (x[i + 1] - x[i - 1]) : f(i + 1) - f(i);
    d1 = i + 2 < n ? w * (f(i + 2) - f(i)) / (x[i + 2] - x[i]) : f(i + 1) - f(i);
}

// The Hermite curve on the unit interval and its integral from 0 to t.
float hermite(float f0, float f1, float d0, float d1, float t) {
    const float t2 = t * t, t3 = t2 * t;
    return (2.f * t3 - 3.f * t2 + 1.f) * f0 + (-2.f * t3 + 3.f * t2) * f1 +
           (t3 - 2.f * t2 + t) * d0 + (t3 - t2) * d1;
}
float hermite_integral(float f0, float f1, float d0, float d1, float t) {
    const float t2 = t * t, t3 = t2 * t, t4 = t3 * t;
    return f0 * (0.5f * t4 - t3 + t) + f1 * (-0.5f * t4 + t3) +
           d0 * (0.25f * t4 - (2.f / 3.f) * t3 + 0.5f * t2) + d1 * (0.25f * t4 - t3 / 3.f);
}

// The t in [0, 1] where g(t) = target for an increasing g with derivative dg: Newton steps,
// kept inside a bracket that bisection shrinks when a step would leave it.
template <class G, class DG>
float solve_unit(G&& g, DG&& dg, float target, float t) {
    float lo = 0.f, hi = 1.f;
    for (int k = 0; k < 64; ++k) {
        if (!(t >= lo && t <= hi)) t = 0.5f * (lo + hi);
        const float r = g(t) - target;
        if (std::fabs(r) < 1e-6f) break;
        (r < 0.f ? lo : hi) = t;
        if (hi - lo < 1e-7f) break;
        const float slope = dg(t);
        t = slope != 0.f ? t - r / slope : 0.5f * (lo + hi);
    }
    return std::clamp(t, 0.f, 1.f);
}

}  // namespace

bool catmull_rom_weights(std::span<const float> nodes, float x, int& offset, float weights[4]) {
    const std::size_t n = nodes.size();
    if (n < 2 || !(x >= nodes[0] && x <= nodes[n - 1])) return false;
    const std::size_t i = interval_of(nodes, x);
    offset = int(i) - 1;
    const float x0 = nodes[i], x1 = nodes[i + 1], w = x1 - x0;
    const float t = (x - x0) / w, t2 = t * t, t3 = t2 * t;
    weights[0] = 0.f;
    weights[1] = 2.f * t3 - 3.f * t2 + 1.f;
    weights[2] = -2.f * t3 + 3.f * t2;
    weights[3] = 0.f;
    // The slope terms: h10 d0 + h11 d1 with d0, d1 the differences of end_slopes.
    const float h10 = t3 - 2.f * t2 + t, h11 = t3 - t2;
    if (i > 0) {
        const float s = h10 * w / (x1 - nodes[i - 1]);
        weights[0] -= s;
        weights[2] += s;
    } else {
        weights[1] -= h10;
        weights[2] += h10;
    }
    if (i + 2 < n) {
        const float s = h11 * w / (nodes[i + 2] - x0);
        weights[1] -= s;
        weights[3] += s;
    } else {
        weights[1] -= h11;
        weights[2] += h11;
    }
    return true;
}

float integrate_catmull_rom(std::span<const float> nodes, std::span<const float> values,
                            std::span<float> cdf) {
    double sum = 0.0;
    cdf[0] = 0.f;
    auto f = [&](std::size_t k) { return values[k]; };
    for (std::size_t i = 0; i + 1 < nodes.size(); ++i) {
        float d0, d1;
        end_slopes(nodes, i, f, d0, d1);
        const float w = nodes[i + 1] - nodes[i];
        sum += double(w) * double(hermite_integral(values[i], values[i + 1], d0, d1, 1.f));
        cdf[i + 1] = float(sum);
    }
    return float(sum);
}

float invert_catmull_rom(std::span<const float> nodes, std::span<const float> values, float y) {
    const std::size_t n = nodes.size();
    if (!(y > values[0])) return nodes[0];
    if (!(y < values[n - 1])) return nodes[n - 1];
    const std::size_t i = interval_of(values, y);
    auto f = [&](std::size_t k) { return values[k]; };
    float d0, d1;
    end_slopes(nodes, i, f, d0, d1);
    const float f0 = values[i], f1 = values[i + 1];
    const float t = solve_unit([&](float s) { return hermite(f0, f1, d0, d1, s); },
                               [&](float s) {
                                   const float s2 = s * s;
                                   return (6.f * s2 - 6.f * s) * (f0 - f1) +
                                          (3.f * s2 - 4.f * s + 1.f) * d0 +
                                          (3.f * s2 - 2.f * s) * d1;
                               },
                               y, (y - f0) / (f1 - f0));
    return nodes[i] + t * (nodes[i + 1] - nodes[i]);
}

float sample_catmull_rom_2d(std::span<const float> nodes1, std::span<const float> nodes2,
                            std::span<const float> values, std::span<const float> cdf, float alpha,
                            float u, float* value, float* pdf) {
    const std::size_t n2 = nodes2.size();
    int offset = 0;
    float w[4];
    if (!catmull_rom_weights(nodes1, alpha, offset, w)) return 0.f;
    // The profile at alpha: each row weighted (rows outside the table have weight zero).
    auto interpolate = [&](std::span<const float> table, std::size_t k) {
        float s = 0.f;
        for (int j = 0; j < 4; ++j)
            if (w[j] != 0.f) s += w[j] * table[std::size_t(offset + j) * n2 + k];
        return s;
    };
    const float total = interpolate(cdf, n2 - 1);
    if (!(total > 0.f)) return 0.f;
    u *= total;
    // The last node whose running integral is at most u.
    std::size_t lo = 0, hi = n2 - 1;
    while (lo + 1 < hi) {
        const std::size_t mid = (lo + hi) / 2;
        (interpolate(cdf, mid) <= u ? lo : hi) = mid;
    }
    const std::size_t i = lo;
    const float f0 = interpolate(values, i), f1 = interpolate(values, i + 1);
    const float x0 = nodes2[i], width = nodes2[i + 1] - x0;
    float d0, d1;
    end_slopes(
        nodes2, i, [&](std::size_t k) { return interpolate(values, k); }, d0, d1);
    // The remaining integral in units of t, inverted; the start is the linear profile's answer.
    const float target = (u - interpolate(cdf, i)) / width;
    float t0;
    if (f0 != f1)
        t0 = (f0 - std::sqrt(std::max(0.f, f0 * f0 + 2.f * target * (f1 - f0)))) / (f0 - f1);
    else
        t0 = f0 > 0.f ? target / f0 : 0.5f;
    const float t = solve_unit([&](float s) { return hermite_integral(f0, f1, d0, d1, s); },
                               [&](float s) { return hermite(f0, f1, d0, d1, s); }, target, t0);
    const float fx = hermite(f0, f1, d0, d1, t);
    if (value) *value = fx;
    if (pdf) *pdf = fx / total;
    return x0 + width * t;
}

}  // namespace foton
