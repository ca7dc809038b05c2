#include "colorimetry.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "cie_tables.h"

namespace foton {

namespace {

// Linear interpolation in a 5 nm table; zero outside it.
float table_at(const float* t, float lambda) {
    const float x = (lambda - cie::kLambdaMin) / cie::kStep;
    if (!(x >= 0.f) || x > float(cie::kSamples - 1)) return 0.f;
    const std::size_t i = std::min(std::size_t(x), cie::kSamples - 2);
    const float f = x - float(i);
    return t[i] * (1.f - f) + t[i + 1] * f;
}

// The integrals the film's estimate converges to, over the tables as interpolated above (a
// 0.05 nm midpoint rule: the interpolated products are piecewise quadratic).
struct Colorimetry {
    double d65_luminance = 0.0;  // integral of y-bar D65
    double to_srgb[3][3] = {};   // XYZ -> linear sRGB
    Colorimetry() {
        const int n = 9400;
        const double h = double(cie::kLambdaMax - cie::kLambdaMin) / n;
        double white[3] = {0.0, 0.0, 0.0};
        for (int i = 0; i < n; ++i) {
            const float l = float(cie::kLambdaMin + (i + 0.5) * h);
            const double e = table_at(cie::kD65, l) * h;
            white[0] += table_at(cie::kX, l) * e;
            white[1] += table_at(cie::kY, l) * e;
            white[2] += table_at(cie::kZ, l) * e;
        }
        d65_luminance = white[1];
        for (double& w : white) w /= d65_luminance;
        // RGB -> XYZ: the primaries' XYZ (luminance 1) as columns, each scaled so that RGB
        // (1, 1, 1) is the white; then inverted.
        const double px[3] = {0.64, 0.30, 0.15}, py[3] = {0.33, 0.60, 0.06};
        double p[3][3];
        for (int c = 0; c < 3; ++c) {
            p[0][c] = px[c] / py[c];
            p[1][c] = 1.0;
            p[2][c] = (1.0 - px[c] - py[c]) / py[c];
        }
        double pinv[3][3];
        invert(p, pinv);
        double s[3];
        for (int r = 0; r < 3; ++r)
            s[r] = pinv[r][0] * white[0] + pinv[r][1] * white[1] + pinv[r][2] * white[2];
        double m[3][3];
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) m[r][c] = p[r][c] * s[c];
        invert(m, to_srgb);
    }
    static void invert(const double a[3][3], double out[3][3]) {
        const double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                           a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) {
                // The cofactor of a[c][r] over the determinant.
                const int r1 = (c + 1) % 3, r2 = (c + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
                out[r][c] = (a[r1][c1] * a[r2][c2] - a[r1][c2] * a[r2][c1]) / det;
            }
    }
};

const Colorimetry& colorimetry() {
    static const Colorimetry c;
    return c;
}

}  // namespace

RGB cie_xyz(float lambda) {
    return {table_at(cie::kX, lambda), table_at(cie::kY, lambda), table_at(cie::kZ, lambda)};
}

float d65_normalised(float lambda) {
    return float(table_at(cie::kD65, lambda) / colorimetry().d65_luminance);
}

RGB xyz_to_linear_srgb(const RGB& xyz) {
    const auto& m = colorimetry().to_srgb;
    auto row = [&](int r) { return float(m[r][0] * xyz.r + m[r][1] * xyz.g + m[r][2] * xyz.b); };
    return {row(0), row(1), row(2)};
}

}  // namespace foton
