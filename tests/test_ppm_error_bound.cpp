// Progressive photon mapping's error bound and stopping rule (ppm_error_bound.h; the
// photon-mapping thesis' 8.1.1): the bound's statistics on synthetic passes with known means,
// and the rule on the Cornell boxes against pbrt-v4's references.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "engine/accel/intersector.h"
#include "engine/core/rng.h"
#include "engine/film/aov.h"
#include "engine/film/image_io.h"
#include "engine/film/metrics.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/photon/ppm_error_bound.h"
#include "engine/transport/registry/render.h"
#include "test_util.h"

using namespace foton;

namespace {

// A standard normal variate from two uniforms (Box-Muller).
float gauss(uint64_t seed, uint64_t i, uint32_t dim) {
    const float u1 = std::max(rng::uniform(seed, 7, i, dim), 1e-12f);
    const float u2 = rng::uniform(seed, 7, i, dim + 1);
    return std::sqrt(-2.f * std::log(u1)) * std::cos(2.f * float(kPi) * u2);
}

struct Coverage {
    double covered = 0.0;     // fraction of pixels whose error is within the bound
    double mean_bound = 0.0;  // of the green channel
};

// `pixels` pixels of true value 1 estimated over `passes` passes whose noise grows as the
// radius shrinks (sigma_j ~ j^(1/6), PPM's) and whose bias b_j = beta / j^(1/3) is known
// to the pass up to noise of `bias_noise` x the pass's (`bias_seen` 0: the passes do not
// estimate it).
Coverage synthetic(uint32_t pixels, uint32_t passes, float beta, float bias_noise, float confidence,
                   float bias_seen = 1.f) {
    PpmErrorBound bound(pixels, confidence);
    std::vector<double> sum(pixels, 0.0);
    for (uint32_t p = 0; p < pixels; ++p)
        for (uint32_t j = 0; j < passes; ++j) {
            const float sigma = 0.2f * std::pow(float(j + 1), 1.f / 6.f);
            const float bias = beta / std::cbrt(float(j + 1));
            const float y = 1.f + bias + sigma * gauss(11, p, 4 * j);
            const float b = bias_seen * bias + bias_noise * sigma * gauss(11, p, 4 * j + 2);
            sum[p] += y;
            bound.record(p, RGB(y), RGB(b));
        }
    Coverage c;
    for (uint32_t p = 0; p < pixels; ++p) {
        const float err = float(std::fabs(sum[p] / passes - 1.0));
        const float b = bound.bound(p, passes).g;
        c.covered += err <= b;
        c.mean_bound += b;
    }
    c.covered /= pixels;
    c.mean_bound /= pixels;
    return c;
}

// A Cornell box at 32 x 32 for `type` (ppm, sppm) with the stopping rule at 25 %.
TestScene stopping_box(const char* scene, const char* type) {
    TestScene s = load_scene(test::source_path(scene));
    s.set_resolution(32, 32);
    s.render.integrator = type;
    s.render.photon.initial_radius = 4.f;
    s.render.photon.photons_per_pass = 65536;
    s.render.photon.stop_error = 0.25f;
    return s;
}

// Pixel i's scalar bound: the luminance of its ErrorBound channels.
double bound_luminance(const AovLayer& layer, std::size_t i) {
    return RGB{layer.at(i, 0), layer.at(i, 1), layer.at(i, 2)}.luminance();
}

double luminance_error(const Film& a, const Film& b, std::size_t i) {
    return std::fabs(double(a.pixels[i].luminance()) - double(b.pixels[i].luminance()));
}

}  // namespace

TEST_CASE("the PPM error bound's t quantile and variance estimate cover at their confidence",
          "[photon][ppm][error_bound]") {
    PpmErrorBound b(1, 0.95f);
    CHECK(b.t_factor(1) == 0.0);
    CHECK(b.t_factor(2) == Approx(12.7062).epsilon(1e-4));  // t_{1, 0.975}
    CHECK(b.t_factor(11) == Approx(2.2281).epsilon(1e-4));  // t_{10, 0.975}
    CHECK(b.t_factor(100000) == Approx(1.95996).epsilon(1e-4));
    // Unbiased passes with growing noise and exact (zero) bias estimates: the bound holds at
    // its confidence, no more (Student's t over passes of unequal variance).
    for (const uint32_t passes : {8u, 64u}) {
        INFO(passes << " passes");
        const Coverage c95 = synthetic(20000, passes, 0.f, 0.f, 0.95f);
        CHECK(c95.covered == Approx(0.95).margin(0.01));
        const Coverage c70 = synthetic(20000, passes, 0.f, 0.f, 0.7f);
        CHECK(c70.covered == Approx(0.7).margin(0.015));
        CHECK(c70.mean_bound < c95.mean_bound);
    }
    // A bias the passes estimate with noise of their own (0.3 x the estimate's, as SPPM's
    // 2R-disc estimate has): the bound covers it and becomes conservative, but not uselessly
    // so; without its bias term it would cover far less.
    const Coverage biased = synthetic(20000, 64, 0.15f, 0.3f, 0.95f);
    CHECK(biased.covered >= 0.95);
    CHECK(biased.covered <= 0.995);
    const Coverage unestimated = synthetic(20000, 64, 0.15f, 0.f, 0.95f, 0.f);
    CHECK(unestimated.covered < 0.8);
}

TEST_CASE("SPPM's stopping rule stops within its error bound on the Cornell boxes",
          "[photon][sppm][error_bound][reference]") {
    struct Box {
        const char* scene;
        const char* reference;
    };
    for (const Box box :
         {Box{"scenes/cornell-caustics.xml", "refs/cornell_caustics_sppm_256it.exr"},
          Box{"scenes/cornell-diffuse.xml", "refs/cornell_diffuse_path_512spp.exr"}}) {
        INFO(box.scene);
        TestScene s = stopping_box(box.scene, "sppm");
        const RenderResult r = render_test(s, 400);  // 400 passes: the cap
        const Film ref = downsample(read_exr(test::shared_path(box.reference)), 16);
        // It stopped by the rule, with the bound it reports under the goal.
        INFO("passes " << r.stats.passes << ", mean bound " << r.stats.error_bound
                       << ", mean luminance " << r.stats.error_mean_value);
        CHECK(r.stats.passes >= PpmErrorBound::kMinPasses);
        CHECK(r.stats.passes < 400);
        CHECK(r.stats.error_confidence == 0.95f);
        CHECK(r.stats.error_bound <= 0.25 * r.stats.error_mean_value);
        // The bound as an AOV; the actual error against pbrt-v4 is within it: on average, and
        // pixel by pixel at (about) its confidence (the reference has noise of its own).
        const AovLayer* layer = find_aov(r.aovs, "error_bound");
        REQUIRE(layer != nullptr);
        double err = 0.0, bound = 0.0, covered = 0.0;
        const std::size_t n = ref.pixels.size();
        for (std::size_t i = 0; i < n; ++i) {
            const double e = luminance_error(r.film, ref, i), b = bound_luminance(*layer, i);
            err += e;
            bound += b;
            covered += e <= b;
        }
        INFO("mean error " << err / n << ", mean bound " << bound / n << ", covered "
                           << covered / n);
        CHECK(bound / n == Approx(r.stats.error_bound).epsilon(1e-4));
        CHECK(err / n <= bound / n);
        CHECK(covered / n >= 0.9);
        // Stopping changes nothing but when: the same passes without the rule give the same
        // image.
        s.render.photon.stop_error = 0.f;
        const RenderResult plain = render_test(s, r.stats.passes);
        CHECK(plain.stats.error_confidence == 0.f);
        CHECK(plain.aovs.empty());
        CHECK(compare_images(plain.film, r.film).max_abs == 0.0);
    }
}

TEST_CASE("PPM's stopping rule bounds its visible points' error and is thread-independent",
          "[photon][ppm][error_bound][reference]") {
    const TestScene s = stopping_box("scenes/cornell-diffuse.xml", "ppm");
    const RenderResult r = render_test(s, 400, 2);
    INFO("passes " << r.stats.passes);
    CHECK(r.stats.passes < 400);
    CHECK(r.stats.error_bound <= 0.25 * r.stats.error_mean_value);
    // PPM's pixel is its one visible point's radiance, not the pixel's average as the
    // reference's is: compared where the reference is smooth over the pixel's neighbours.
    const Film ref =
        downsample(read_exr(test::shared_path("refs/cornell_diffuse_path_512spp.exr")), 16);
    const AovLayer* layer = find_aov(r.aovs, "error_bound");
    REQUIRE(layer != nullptr);
    double err = 0.0, bound = 0.0, mean = 0.0;
    int smooth = 0;
    for (const RGB& p : ref.pixels) mean += p.luminance();
    mean /= double(ref.pixels.size());
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            float lo = 1e30f, hi = -1e30f;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const float v =
                        ref.at(std::clamp(x + dx, 0, 31), std::clamp(y + dy, 0, 31)).luminance();
                    lo = std::min(lo, v);
                    hi = std::max(hi, v);
                }
            if (hi - lo >= 0.1 * mean) continue;
            const std::size_t i = std::size_t(y) * 32 + std::size_t(x);
            err += luminance_error(r.film, ref, i);
            bound += bound_luminance(*layer, i);
            ++smooth;
        }
    INFO(smooth << " smooth pixels: mean error " << err / smooth << ", mean bound "
                << bound / smooth);
    REQUIRE(smooth > 50);
    CHECK(err <= bound);
    // One thread stops after the same pass with the same image and bound.
    const RenderResult one = render_test(s, 400, 1);
    CHECK(one.stats.passes == r.stats.passes);
    CHECK(compare_images(one.film, r.film).max_abs == 0.0);
    CHECK(one.aovs[0].values == r.aovs[0].values);
}
