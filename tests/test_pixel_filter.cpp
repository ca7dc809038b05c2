// The pixel filter (engine/film/pixel_filter.h): each type's sampler draws offsets with the
// density |f| / its integral (chi-square per axis), the signed weights of Mitchell's and
// Lanczos' samples average 1 and reproduce f, eval integrates to integral(), the 1-pixel box
// leaves positions and splats as they were, a splat's weights are the filter's at the pixel
// centres; and a step edge renders as the step convolved with the filter, by camera paths
// (importance-sampled offsets), light paths (filtered splats), bdpt and MLT alike; filtered
// splats do not depend on the thread count (tests/test_crop.cpp: nor on a crop window).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <vector>

#include "chi_square.h"
#include "engine/core/rng.h"
#include "engine/film/pixel_filter.h"
#include "engine/scene/pbrt_loader.h"
#include "engine/scene/xml_loader.h"
#include "test_util.h"

using namespace foton;

namespace {

std::vector<PixelFilter> filters() {
    return {PixelFilter::box(0.5f, 0.5f),
            PixelFilter::box(1.25f, 0.75f),
            PixelFilter::triangle(2.f, 1.f),
            PixelFilter::gaussian(1.5f, 1.5f, 0.5f),
            PixelFilter::gaussian(2.f, 1.f, 0.8f),
            PixelFilter::mitchell(2.f, 2.f, 1.f / 3.f, 1.f / 3.f),
            PixelFilter::mitchell(1.5f, 2.f, 0.f, 0.5f),
            PixelFilter::lanczos(4.f, 3.f, 3.f)};
}

// The filter's mass on x < t (one axis, normalised), by a fine midpoint rule over eval (or
// over |eval|: the density samples are placed by).
double mass_below(const PixelFilter& f, double t, bool magnitude = false) {
    const int n = 4000;
    const double r = f.radius_x();
    double below = 0.0, all = 0.0;
    for (int i = 0; i < n; ++i) {
        const double x = -r + (i + 0.5) * 2.0 * r / n;
        const double e = f.eval(float(x), 0.f);
        const double v = magnitude ? std::fabs(e) : e;
        all += v;
        if (x < t) below += v;
    }
    return below / all;
}

}  // namespace

TEST_CASE("pixel filter: eval integrates to integral(), samples follow |f|, weights make f",
          "[film][filter][fast]") {
    for (const PixelFilter& f : filters()) {
        INFO(f.describe());
        // The integral over the plane by a midpoint rule.
        const int n = 400;
        const double rx = f.radius_x(), ry = f.radius_y();
        double sum = 0.0;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                sum += f.eval(float(-rx + (i + 0.5) * 2.0 * rx / n),
                              float(-ry + (j + 0.5) * 2.0 * ry / n));
        sum *= 4.0 * rx * ry / (double(n) * n);
        CHECK(sum == Approx(f.integral()).epsilon(2e-3));
        CHECK(f.eval(float(rx) * 1.01f, 0.f) == 0.f);
        // Chi-square of the x offsets over 40 bins against the marginal's bin masses.
        const int bins = 40, samples = 200000;
        std::vector<double> observed(bins, 0.0);
        int outside = 0;
        // The samples' weights: their mean is 1, and weighted they average any function g
        // as f / integral does (here g = x^2 + y: the second moment in x, the mean in y).
        double weight_sum = 0.0, weighted_g = 0.0, want_g = 0.0;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double x = -rx + (i + 0.5) * 2.0 * rx / n, y = -ry + (j + 0.5) * 2.0 * ry / n;
                want_g += f.eval(float(x), float(y)) * (x * x + y);
            }
        want_g *= 4.0 * rx * ry / (double(n) * n) / f.integral();
        for (int s = 0; s < samples; ++s) {
            const Point2 u{rng::uniform(7, 1, uint64_t(s), 0), rng::uniform(7, 1, uint64_t(s), 1)};
            const Point2 p = f.pixel_position(u);
            const double x = double(p.x) - 0.5, y = double(p.y) - 0.5;
            const double w = f.sample_weight(p);
            if (!f.negative_lobes()) CHECK(w == 1.0);
            weight_sum += w;
            weighted_g += w * (x * x + y);
            if (std::fabs(x) > rx + 1e-5 || std::fabs(y) > ry + 1e-5) ++outside;
            observed[std::size_t(std::clamp(int((x + rx) / (2.0 * rx) * bins), 0, bins - 1))] += 1;
        }
        CHECK(outside == 0);
        INFO("mean weight " << weight_sum / samples << ", weighted g " << weighted_g / samples
                            << " against " << want_g);
        CHECK(weight_sum / samples == Approx(1.0).margin(0.01));
        CHECK(weighted_g / samples == Approx(want_g).margin(0.02 * rx * rx));
        double chi2 = 0.0;
        int dof = -1;
        for (int b = 0; b < bins; ++b) {
            const double lo = -rx + 2.0 * rx * b / bins, hi = lo + 2.0 * rx / bins;
            const double e = (mass_below(f, hi, true) - mass_below(f, lo, true)) * samples;
            if (e < 5.0) continue;
            chi2 += (observed[std::size_t(b)] - e) * (observed[std::size_t(b)] - e) / e;
            ++dof;
        }
        const double p = test::gamma_q(0.5 * dof, 0.5 * chi2);
        INFO("chi2 " << chi2 << " dof " << dof << " p " << p);
        CHECK(p > 1e-3);
    }
}

TEST_CASE("pixel filter: the 1-pixel box keeps positions and splats, wider ones spread",
          "[film][filter][fast]") {
    const PixelFilter box;
    CHECK(box.unit_box());
    CHECK(box.margin() == 0.f);
    const Point2 u{0.3f, 0.9f};
    CHECK(box.pixel_position(u).x == u.x);
    CHECK(box.pixel_position(u).y == u.y);
    // A splat at image position (12.7, 5.2) of a film cropped to [10, 20) x [4, 8).
    std::vector<std::pair<uint32_t, float>> got;
    box.spread(12.7f, 5.2f, 10, 4, 10, 4, [&](uint32_t p, float w) { got.push_back({p, w}); });
    REQUIRE(got.size() == 1);
    CHECK(got[0].first == 1u * 10u + 2u);
    CHECK(got[0].second == 1.f);
    got.clear();
    box.spread(9.9f, 5.2f, 10, 4, 10, 4, [&](uint32_t p, float w) { got.push_back({p, w}); });
    CHECK(got.empty());  // off the crop window
    // The Gaussian: the pixels whose centres lie within 1.5, weighted f / integral.
    const PixelFilter g = PixelFilter::gaussian(1.5f, 1.5f, 0.5f);
    CHECK(g.margin() == Approx(1.f));
    double total = 0.0;
    g.spread(12.7f, 5.2f, 10, 4, 10, 4, [&](uint32_t p, float w) {
        const int x = 10 + int(p % 10), y = 4 + int(p / 10);
        CHECK(w == Approx(g.eval(float(x) + 0.5f - 12.7f, float(y) + 0.5f - 5.2f) / g.integral()));
        got.push_back({p, w});
        total += w;
    });
    CHECK(got.size() == 9);  // x 11..13, y 4..6
    // Summed over the integer lattice a Gaussian of sigma 0.5 is flat to a few per cent.
    CHECK(total == Approx(1.0).margin(0.05));
}

TEST_CASE("pixel filter: a step edge renders as the step convolved with the filter",
          "[film][filter][integrators]") {
    // A white Lambertian half-plane (x < 0) before a black background, lit head-on (radiance
    // 1), seen head-on through a perspective camera whose image splits at the edge: columns
    // 0-7 white, 8-15 black for the box; a filter blurs the step by its mass on each side.
    for (const char* filter : {"\"box\"", "\"gaussian\"", "\"triangle\" \"float xradius\" 1.5",
                               "\"mitchell\"", "\"sinc\" \"float xradius\" 3"}) {
        const std::string text =
            std::string(
                "LookAt 0 0 -4  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [20]\n"
                "Film \"rgb\" \"integer xresolution\" [16] \"integer yresolution\" [4]\n"
                "PixelFilter ") +
            filter +
            "\nIntegrator \"path\" \"integer maxdepth\" [1]\nWorldBegin\n"
            "LightSource \"distant\" \"point3 from\" [0 0 -1] \"point3 to\" [0 0 0] \"rgb L\" "
            "[3.14159265 3.14159265 3.14159265]\nMaterial \"diffuse\" \"rgb reflectance\" [1 1 1]\n"
            "Shape \"trianglemesh\" \"point3 P\" [-5 -5 0  0 -5 0  0 5 0  -5 5 0] "
            "\"integer indices\" [0 1 2  0 2 3]\n";
        const TestScene scene(parse_pbrt_scene(text, "edge.pbrt", "."));
        const PixelFilter& f = scene.film.filter;
        INFO(f.describe());
        struct Case {
            const char* integrator;
            uint32_t spp;
            double tolerance;
        };
        for (const Case& c : {Case{"path", 1024, 0.01}, Case{"light", 16384, 0.04},
                              Case{"bdpt", 512, 0.02}, Case{"mlt", 4096, 0.08}}) {
            INFO(c.integrator);
            TestScene s = scene;
            s.render.integrator = c.integrator;
            const Film img = render_test(s, c.spp * test::effort(), 0, 5).film;
            // Which side is white depends on the camera's handedness: read it off column 0.
            double first = 0.0;
            for (int y = 0; y < 4; ++y) first += img.at(0, y).g / 4.0;
            const bool white_left = first > 0.5;
            double worst = 0.0;
            int worst_x = 0;
            for (int x = 0; x < 16; ++x) {
                double mean = 0.0;
                for (int y = 0; y < 4; ++y) mean += img.at(x, y).g / 4.0;
                // The pixel centre's distance from the edge (at 8), towards the white side.
                const double d = white_left ? 8.0 - (x + 0.5) : (x + 0.5) - 8.0;
                const double e = std::fabs(mean - mass_below(f, d));
                if (e > worst) worst_x = x;
                worst = std::max(worst, e);
            }
            // bdpt weighs each camera sample by the filter's sign (an unbiased sum, noisier
            // than the tile driver's weighted mean): twice the margin with negative lobes.
            const double tolerance =
                c.tolerance *
                (f.negative_lobes() && c.integrator == std::string("bdpt") ? 2.25 : 1.0);
            INFO("worst column error " << worst << " at column " << worst_x);
            CHECK(worst < tolerance);
        }
    }
}

TEST_CASE("pixel filter: filtered splats are the same on 1 and 2 threads, bit for bit",
          "[film][filter][integrators]") {
    TestScene s = load_scene(test::source_path("scenes/cornell-caustics.xml"));
    s.set_resolution(24, 24);
    s.film.filter = PixelFilter::gaussian(1.5f, 1.5f, 0.5f);
    for (const char* integrator : {"light", "bdpt", "path"}) {
        INFO(integrator);
        s.render.integrator = integrator;
        const Film one = render_test(s, 4, 1, 9).film, two = render_test(s, 4, 2, 9).film;
        REQUIRE(one.pixels.size() == two.pixels.size());
        CHECK(std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(RGB)) ==
              0);
    }
}
