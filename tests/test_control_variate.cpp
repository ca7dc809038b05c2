// Control variates for direct light (the photon-mapping thesis' 3.2.4): Lambert's polygon
// formula against the closed form of a rectangle's form factor and against numerical
// integration, and the estimator against the plain light sample: the same mean, less noise.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "engine/accel/intersector.h"
#include "engine/core/warp.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/common/direct_control_variate.h"
#include "engine/transport/registry/render.h"
#include "test_util.h"

using namespace foton;

namespace {

// The integral of cos over an a x b rectangle parallel to the receiver at height c, seen from
// under one of its corners: pi times the form factor of the standard table
// (F = 1/(2 pi) [A/sqrt(1+A^2) atan(B/sqrt(1+A^2)) + B/sqrt(1+B^2) atan(A/sqrt(1+B^2))]).
double corner_rectangle(double a, double b, double c) {
    const double A = a / c, B = b / c, sa = std::sqrt(1 + A * A), sb = std::sqrt(1 + B * B);
    return 0.5 * (A / sa * std::atan(B / sa) + B / sb * std::atan(A / sb));
}

// The same integral by quadrature: stratified directions over the hemisphere about `up`,
// each weighted by its cosine, counted where the ray meets the quad (corner, edges).
double numeric_quad(const Vec3& corner, const Vec3& e1, const Vec3& e2, const Vec3& x,
                    const Vec3& up) {
    const warp::Frame frame(up);
    const Vec3 n = cross(e1, e2);
    const int N = 1024;
    double sum = 0.0;
    for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j) {
            // Uniform in solid angle: z = cos theta uniform in [0, 1).
            const float z = (float(i) + 0.5f) / float(N), phi = 2.f * kPi * (float(j) + 0.5f) / N;
            const float r = std::sqrt(1.f - z * z);
            const Vec3 w = frame.to_world({r * std::cos(phi), r * std::sin(phi), z});
            const float dn = dot(w, n);
            if (dn == 0.f) continue;
            const float t = dot(corner - x, n) / dn;
            if (t <= 0.f) continue;
            const Vec3 q = x + w * t - corner;
            // q = s1 e1 + s2 e2: the 2 x 2 Gram system (the edges need not be orthogonal).
            const float g11 = dot(e1, e1), g12 = dot(e1, e2), g22 = dot(e2, e2);
            const float b1 = dot(q, e1), b2 = dot(q, e2), det = g11 * g22 - g12 * g12;
            const float s1 = (b1 * g22 - b2 * g12) / det, s2 = (b2 * g11 - b1 * g12) / det;
            if (s1 >= 0.f && s1 <= 1.f && s2 >= 0.f && s2 <= 1.f) sum += z;
        }
    return sum * 2.0 * kPi / (double(N) * N);
}

}  // namespace

TEST_CASE("Lambert's polygon formula equals the closed form and quadrature", "[cv]") {
    const Vec3 x{0.f, 0.f, 0.f}, up{0.f, 0.f, 1.f};
    // A 2 x 3 rectangle at height 1.5 whose corner is straight above x.
    const Vec3 rect[4] = {{0, 0, 1.5f}, {2, 0, 1.5f}, {2, 3, 1.5f}, {0, 3, 1.5f}};
    CHECK(polygon_cosine_integral(rect, 4, x, up) ==
          Approx(corner_rectangle(2, 3, 1.5)).epsilon(1e-5));
    // Centred: four corner rectangles. Winding does not matter.
    const Vec3 centred[4] = {{-1, -1.5f, 2}, {-1, 1.5f, 2}, {1, 1.5f, 2}, {1, -1.5f, 2}};
    CHECK(polygon_cosine_integral(centred, 4, x, up) ==
          Approx(4.0 * corner_rectangle(1, 1.5, 2)).epsilon(1e-5));
    // Wholly below the horizon: nothing; a huge one just above x: almost the whole pi.
    const Vec3 below[3] = {{0, 0, -1}, {1, 0, -1}, {0, 1, -2}};
    CHECK(polygon_cosine_integral(below, 3, x, up) == 0.f);
    const Vec3 huge[4] = {{-1e4f, -1e4f, 1}, {1e4f, -1e4f, 1}, {1e4f, 1e4f, 1}, {-1e4f, 1e4f, 1}};
    CHECK(polygon_cosine_integral(huge, 4, x, up) == Approx(kPi).epsilon(1e-3));
    // Tilted quads cut by the horizon (the clipped case), against quadrature.
    struct Quad {
        Vec3 corner, e1, e2;
    };
    for (const Quad& q : {Quad{{-1, 0.5f, -0.5f}, {2, 0, 0}, {0, 0.5f, 1.5f}},
                          Quad{{0.3f, -1, -1}, {0, 2, 0}, {0.8f, 0, 2}},
                          Quad{{-2, 1, 0.2f}, {3, 0.5f, 0}, {0, 1, 1}}}) {
        const Vec3 c[4] = {q.corner, q.corner + q.e1, q.corner + q.e1 + q.e2, q.corner + q.e2};
        const double exact = polygon_cosine_integral(c, 4, x, up);
        CHECK(exact > 0.01);
        CHECK(exact == Approx(numeric_quad(q.corner, q.e1, q.e2, x, up)).epsilon(2e-3));
    }
}

TEST_CASE("the control variate keeps the direct light's mean and removes its noise where lit",
          "[cv][photon]") {
    // Direct light only in the diffuse Cornell box (a rectangle light, Lambertian walls and
    // blocks): the plain light sample and the control-variate estimate, two seeds each.
    auto run = [](bool cv, uint64_t seed) {
        TestScene s = load_scene(test::source_path("scenes/cornell-diffuse.xml"));
        s.set_resolution(48, 48);
        s.render.integrator = "photon";
        s.render.lighting = Lighting::Direct;
        s.render.photon.global_photons = 1000;
        s.render.photon.caustic_photons = 0;
        s.render.photon.direct_control_variate = cv;
        return render_test(s, 8, 0, seed).film;
    };
    const Film plain[2] = {run(false, 1), run(false, 2)};
    const Film cv[2] = {run(true, 1), run(true, 2)};
    // Means over the whole image agree (unbiased): within the plain estimate's own noise.
    double m[2][2] = {{0, 0}, {0, 0}};
    for (int k = 0; k < 2; ++k)
        for (const RGB& p : plain[k].pixels) m[0][k] += p.g;
    for (int k = 0; k < 2; ++k)
        for (const RGB& p : cv[k].pixels) m[1][k] += p.g;
    const double mp = 0.5 * (m[0][0] + m[0][1]), mc = 0.5 * (m[1][0] + m[1][1]);
    INFO("plain " << mp << " control variate " << mc);
    CHECK(mc == Approx(mp).epsilon(0.01));
    // Noise: the relative difference between seeds per pixel, over lit pixels (a light sample
    // at most pixels sees the whole light: the control variate is exact there).
    std::vector<double> dp, dc;
    for (std::size_t i = 0; i < plain[0].pixels.size(); ++i) {
        const double a = plain[0].pixels[i].g, b = plain[1].pixels[i].g;
        if (a < 0.02 || a > 1.0) continue;  // dark, or the light itself
        dp.push_back(std::fabs(a - b) / a);
        dc.push_back(std::fabs(cv[0].pixels[i].g - cv[1].pixels[i].g) / a);
    }
    REQUIRE(dp.size() > 500);
    auto median = [](std::vector<double> v) {
        std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
        return v[v.size() / 2];
    };
    INFO("median relative difference between seeds: plain " << median(dp) << ", control variate "
                                                            << median(dc));
    CHECK(median(dc) < 0.2 * median(dp));
}
