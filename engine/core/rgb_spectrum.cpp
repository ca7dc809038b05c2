#include "rgb_spectrum.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "cie_tables.h"
#include "colorimetry.h"

namespace foton {

namespace {

constexpr float kRange = cie::kLambdaMax - cie::kLambdaMin;

// The fit's quadrature: two Gauss-Legendre points in each 5 nm step of the tables, so the
// integral it takes is the one the film's estimate converges to (the tables interpolated
// linearly, their product quadratic in a step) up to the spectrum's own curvature. Each
// point's weight is the colour matching functions times D65 taken to linear sRGB,
// normalised so that the constant spectrum 1 is exactly (1, 1, 1) under this rule.
struct FitQuadrature {
    static constexpr std::size_t kPoints = 2 * (cie::kSamples - 1);
    double t[kPoints];
    double w[kPoints][3];
    FitQuadrature() {
        double white[3] = {0.0, 0.0, 0.0};
        const double g = 0.5 / std::sqrt(3.0);
        for (std::size_t k = 0; k < kPoints; ++k) {
            const double x = double(k / 2) + 0.5 + ((k & 1) ? g : -g);  // in table steps
            const float lambda = float(cie::kLambdaMin + x * cie::kStep);
            t[k] = x / double(cie::kSamples - 1);
            const RGB rgb = xyz_to_linear_srgb(cie_xyz(lambda));
            const double e = d65_normalised(lambda);
            w[k][0] = rgb.r * e;
            w[k][1] = rgb.g * e;
            w[k][2] = rgb.b * e;
            for (int c = 0; c < 3; ++c) white[c] += w[k][c];
        }
        for (auto& wk : w)
            for (int c = 0; c < 3; ++c) wk[c] /= white[c];
    }
};

const FitQuadrature& quadrature() {
    static const FitQuadrature q;
    return q;
}

// The sRGB colour of coefficients c and its Jacobian d rgb / d c.
void colour_of(const double c[3], double rgb[3], double jac[3][3]) {
    const FitQuadrature& q = quadrature();
    for (int i = 0; i < 3; ++i) {
        rgb[i] = 0.0;
        for (int j = 0; j < 3; ++j) jac[i][j] = 0.0;
    }
    for (std::size_t k = 0; k < FitQuadrature::kPoints; ++k) {
        const double t = q.t[k];
        const double x = (c[0] * t + c[1]) * t + c[2];
        const double xc = std::clamp(x, -1e150, 1e150);  // x^2 stays finite
        const double r = 1.0 / std::sqrt(1.0 + xc * xc);
        const double s = 0.5 + 0.5 * xc * r;
        const double ds = 0.5 * r * r * r;  // d s / d x
        const double dx[3] = {t * t, t, 1.0};
        for (int i = 0; i < 3; ++i) {
            rgb[i] += q.w[k][i] * s;
            for (int j = 0; j < 3; ++j) jac[i][j] += q.w[k][i] * ds * dx[j];
        }
    }
}

double max_error(const double a[3], const double b[3]) {
    return std::max({std::fabs(a[0] - b[0]), std::fabs(a[1] - b[1]), std::fabs(a[2] - b[2])});
}

// Solves a x = b (3 x 3) by Cramer's rule; false when a is singular.
bool solve3(const double a[3][3], const double b[3], double x[3]) {
    auto det = [](const double m[3][3]) {
        return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
               m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    };
    const double d = det(a);
    if (!(std::fabs(d) > 1e-300)) return false;
    for (int j = 0; j < 3; ++j) {
        double m[3][3];
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) m[r][c] = c == j ? b[r] : a[r][c];
        x[j] = det(m) / d;
    }
    return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
}

// The smoothstep spacing of the table's largest-channel axis, twice applied: nodes crowd
// towards 0 and 1, where the coefficients change fastest.
float smoothstep(float x) {
    return x * x * (3.f - 2.f * x);
}

}  // namespace

float SigmoidPolynomial::operator()(float lambda) const {
    const float t = (lambda - cie::kLambdaMin) * (1.f / kRange);
    // Clamped so that x^2 stays finite (a grey's constant may be 1e30: s = 1).
    const float x = std::clamp((c0 * t + c1) * t + c2, -1e18f, 1e18f);
    return 0.5f + 0.5f * x / std::sqrt(1.f + x * x);
}

SigmoidPolynomial fit_sigmoid_polynomial(const RGB& rgb, SigmoidPolynomial start, float* residual) {
    const double target[3] = {std::clamp(double(rgb.r), 0.0, 1.0),
                              std::clamp(double(rgb.g), 0.0, 1.0),
                              std::clamp(double(rgb.b), 0.0, 1.0)};
    double c[3] = {start.c0, start.c1, start.c2};
    double cur[3], jac[3][3];
    colour_of(c, cur, jac);
    double err = max_error(cur, target);
    for (int it = 0; it < 64 && err > 1e-7; ++it) {
        const double r[3] = {target[0] - cur[0], target[1] - cur[1], target[2] - cur[2]};
        double step[3];
        if (!solve3(jac, r, step)) break;
        // Backtracking: halve the Newton step until the error falls.
        bool improved = false;
        for (int h = 0; h < 24 && !improved; ++h) {
            const double next[3] = {c[0] + step[0], c[1] + step[1], c[2] + step[2]};
            double rgb_next[3], jac_next[3][3];
            colour_of(next, rgb_next, jac_next);
            const double e = max_error(rgb_next, target);
            if (e < err) {
                improved = true;
                err = e;
                for (int i = 0; i < 3; ++i) {
                    c[i] = next[i];
                    cur[i] = rgb_next[i];
                    for (int j = 0; j < 3; ++j) jac[i][j] = jac_next[i][j];
                }
            }
            for (double& s : step) s *= 0.5;
        }
        if (!improved) break;
    }
    if (residual) *residual = float(err);
    return {float(c[0]), float(c[1]), float(c[2])};
}

const RgbSpectrumTable& RgbSpectrumTable::get() {
    static const RgbSpectrumTable table;
    return table;
}

RgbSpectrumTable::RgbSpectrumTable() : coeffs_(std::size_t(3) * kRes * kRes * kRes * 3) {
    for (int k = 0; k < kRes; ++k)
        z_nodes_[std::size_t(k)] = smoothstep(smoothstep(float(k) / float(kRes - 1)));
    // Each (largest channel, x, y) column of fits along z from a fifth of the way up, each fit
    // starting from its neighbour's (the colours change little between nodes).
    tbb::parallel_for(0, 3 * kRes, [&](int job) {
        const int l = job / kRes, xi = job % kRes;
        const float x = float(xi) / float(kRes - 1);
        for (int yi = 0; yi < kRes; ++yi) {
            const float y = float(yi) / float(kRes - 1);
            auto fit = [&](int zi, SigmoidPolynomial from) {
                const float z = z_nodes_[std::size_t(zi)];
                float v[3];
                v[l] = z;
                v[(l + 1) % 3] = x * z;
                v[(l + 2) % 3] = y * z;
                const SigmoidPolynomial s = fit_sigmoid_polynomial(RGB{v[0], v[1], v[2]}, from);
                float* out = &coeffs_[index(l, zi, yi, xi)];
                out[0] = s.c0;
                out[1] = s.c1;
                out[2] = s.c2;
                return s;
            };
            const int start = kRes / 5;
            SigmoidPolynomial s = fit(start, {});
            const SigmoidPolynomial first = s;
            for (int zi = start + 1; zi < kRes; ++zi) s = fit(zi, s);
            s = first;
            for (int zi = start - 1; zi >= 0; --zi) s = fit(zi, s);
        }
    });
}

SigmoidPolynomial RgbSpectrumTable::reflectance(const RGB& in) const {
    const float v[3] = {std::clamp(in.r, 0.f, 1.f), std::clamp(in.g, 0.f, 1.f),
                        std::clamp(in.b, 0.f, 1.f)};
    if (v[0] == v[1] && v[1] == v[2]) {
        // A grey is a constant: s = v where x = (2v - 1) / sqrt(1 - (2v - 1)^2).
        const double y = 2.0 * v[0] - 1.0;
        const double x = std::fabs(y) >= 1.0 ? std::copysign(1e30, y) : y / std::sqrt(1.0 - y * y);
        return {0.f, 0.f, float(x)};
    }
    const int l = v[0] >= v[1] ? (v[0] >= v[2] ? 0 : 2) : (v[1] >= v[2] ? 1 : 2);
    const float z = v[l];
    const float xf = v[(l + 1) % 3] / z * float(kRes - 1);
    const float yf = v[(l + 2) % 3] / z * float(kRes - 1);
    const int xi = std::min(int(xf), kRes - 2), yi = std::min(int(yf), kRes - 2);
    const int zi =
        int(std::upper_bound(z_nodes_.begin() + 1, z_nodes_.end() - 1, z) - z_nodes_.begin()) - 1;
    const float fx = xf - float(xi), fy = yf - float(yi);
    const float fz = (z - z_nodes_[std::size_t(zi)]) /
                     (z_nodes_[std::size_t(zi + 1)] - z_nodes_[std::size_t(zi)]);
    float c[3] = {0.f, 0.f, 0.f};
    for (int dz = 0; dz < 2; ++dz)
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) {
                const float w = (dz ? fz : 1.f - fz) * (dy ? fy : 1.f - fy) * (dx ? fx : 1.f - fx);
                const float* p = at(l, zi + dz, yi + dy, xi + dx);
                for (int k = 0; k < 3; ++k) c[k] += w * p[k];
            }
    return {c[0], c[1], c[2]};
}

}  // namespace foton
