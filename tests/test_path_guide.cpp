// Photon-guided path tracing: the sphere histogram's sampler against its density, the
// guide/BSDF mixture against its density and its weight, and the guided path tracer's image
// (unbiased, deterministic, less noisy where caustics light the room), plus its settings.
#include <catch2/catch.hpp>

#include "chi_square.h"
#include "engine/accel/intersector.h"
#include "engine/core/rng.h"
#include "engine/core/sphere_histogram.h"
#include "engine/film/image_io.h"
#include "engine/film/metrics.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/path/path_guide.h"
#include "engine/transport/registry/render.h"
#include "test_util.h"

using namespace foton;

namespace {

// Most weight from one bright direction, some from a second, as the photons of a bin lit
// through a glass sphere and off a wall would give.
SphereHistogram two_lobes() {
    SphereHistogram h;
    h.clear();
    const Vec3 bright = normalize(Vec3{0.6f, -0.3f, 0.5f}),
               dim = normalize(Vec3{-0.2f, 0.7f, -0.4f});
    for (int i = 0; i < 400; ++i) {
        const Vec3 jitter{0.3f * (rng::uniform(5, 1, uint64_t(i), 0) - 0.5f),
                          0.3f * (rng::uniform(5, 1, uint64_t(i), 1) - 0.5f),
                          0.3f * (rng::uniform(5, 1, uint64_t(i), 2) - 0.5f)};
        h.add(normalize((i % 4 ? bright : dim) + jitter), 1.f + float(i % 3));
    }
    h.add({0.f, 0.f, 1.f}, 0.f);  // no weight: not counted
    return h;
}

RenderResult run(const TestScene& scene, uint32_t spp, int threads = 0, uint64_t seed = 1) {
    return render_test(scene, spp, threads, seed);
}

}  // namespace

TEST_CASE("the sphere histogram's sampler matches its density (chi-square)", "[guide][fast]") {
    SphereHistogram h = two_lobes();
    CHECK(h.count() == 400);
    REQUIRE(h.finish(0.05f));
    test::ChiSquareSetup setup;
    setup.samples = 200000;
    // The density jumps at the cells' edges, which cut the test's (theta, phi) bins: a finer
    // midpoint rule keeps the expected counts exact enough.
    setup.quad = 64;
    const auto r = test::chi_square(
        setup,
        [&](int i, Vec3& wi) {
            float pdf;
            wi = h.sample({rng::uniform(6, 2, uint64_t(i), 0), rng::uniform(6, 2, uint64_t(i), 1)},
                          pdf);
            return std::fabs(pdf - h.pdf(wi)) <= 1e-4f * pdf && std::fabs(length(wi) - 1.f) < 1e-4f;
        },
        [&](const Vec3& wi) { return double(h.pdf(wi)); });
    INFO(r.summary());
    CHECK(r.p_value > 1e-3);
    CHECK(r.expected_total == Approx(1.0).margin(0.01));
    CHECK(r.observed_total == Approx(1.0).margin(0.001));
    // The floor keeps every direction possible; an empty histogram declines.
    CHECK(h.pdf(normalize(Vec3{0.1f, 0.1f, -1.f})) > 0.f);
    SphereHistogram empty;
    empty.clear();
    CHECK_FALSE(empty.finish(0.05f));
}

TEST_CASE("the guide/BSDF mixture: density matches samples, weight estimates the albedo",
          "[guide][fast]") {
    SphereHistogram h = two_lobes();
    REQUIRE(h.finish(0.05f));
    Bsdf lambert;
    lambert.add(Lobe::lambert(RGB{0.6f, 0.4f, 0.2f}));
    REQUIRE(guidable(lambert));
    // A shading frame tilted against the world (the histogram lives in world space).
    const warp::Frame frame(normalize(Vec3{0.3f, -0.2f, 0.9f}));
    const Vec3 wo = normalize(Vec3{0.2f, 0.1f, 0.8f});
    const BsdfContext ctx{true, Transport::Radiance};
    for (float alpha : {0.3f, 0.7f}) {
        const GuideMixture mix{&h, alpha};
        test::ChiSquareSetup setup;
        setup.axis = frame.n;
        setup.theta_max = 0.5f * kPi;
        setup.samples = 200000;
        double weight = 0.0;
        int n = 0;
        const auto r = test::chi_square(
            setup,
            [&](int i, Vec3& wi) {
                BsdfSample bs;
                float bsdf_pdf;
                ++n;
                if (!sample_mixture(
                        lambert, wo, frame, ctx, mix, rng::uniform(7, 3, uint64_t(i), 0),
                        {rng::uniform(7, 3, uint64_t(i), 1), rng::uniform(7, 3, uint64_t(i), 2)},
                        bs, bsdf_pdf))
                    return false;
                wi = frame.to_world(bs.wi);
                // The density the sampler reports is the mixture's, as MIS evaluates it.
                const float expect = mix.pdf(lambert.pdf(wo, bs.wi, ctx), wi);
                if (std::fabs(bs.pdf - expect) > 1e-4f * expect) return false;
                weight += double(bs.f.r * std::fabs(bs.wi.z) / bs.pdf);
                return true;
            },
            [&](const Vec3& wi) {
                const Vec3 l = frame.to_local(wi);
                return l.z <= 0.f ? 0.0 : double(mix.pdf(lambert.pdf(wo, l, ctx), wi));
            });
        INFO("alpha " << alpha << ": " << r.summary());
        CHECK(r.p_value > 1e-3);
        // Guided directions below the surface carry nothing: the success rate is the
        // density's mass over the hemisphere.
        CHECK(r.observed_total == Approx(r.expected_total).margin(0.01));
        // f cos / pdf averages to the albedo over every draw (failed ones count as zero).
        CHECK(weight / n == Approx(0.6).epsilon(0.01));
    }
}

TEST_CASE("guided path tracing converges to the same image with less noise",
          "[guide][integrator]") {
    // The white furnace without next event estimation, where the direct photons guide every
    // bounce: Le / (1 - a).
    const TestScene f(parse_scene(R"(<scene><objects><sphere radius="1"><center x="0" y="0" z="0"/>
        <material type="lambert"><reflectance r="0.6" g="0.6" b="0.6"/>
        <emission r="0.5" g="0.5" b="0.5" two_sided="true"/></material></sphere></objects>
        <film width="16" height="16"/>
        <renderer type="path" nee="false" max_depth="100" guided="true" guide_emitted="20000"/>
        <camera fov="60"><eye x="0" y="0" z="0"/><target x="0" y="0" z="1"/></camera></scene>)",
                                  "furnace.xml", "."));
    const RenderResult fr = run(f, 256);
    // The guide holds bins (the build-guide node reports how many), so the mixture is used.
    uint64_t bins = 0;
    for (const GraphStats::Node& node : fr.stats.graph.nodes)
        if (node.name == "build-guide") bins = node.items;
    REQUIRE(bins > 0);
    double sum = 0.0;
    for (const RGB& p : fr.film.pixels) sum += p.g;
    CHECK(sum / double(fr.film.pixels.size()) == Approx(0.5 / 0.4).epsilon(0.01));

    // The caustics box: the mirror's and the glass sphere's caustics reach every wall, found
    // only by BSDF sampling unless guided. Same mean as pbrt-v4's reference, and less error
    // than unguided at the same samples.
    TestScene s = load_scene(test::source_path("scenes/cornell-caustics.xml"));
    s.set_resolution(64, 64);
    const Film ref =
        downsample(read_exr(test::shared_path("refs/cornell_caustics_sppm_256it.exr")), 8);
    const std::vector<uint8_t> mask = luminance_mask(ref, 2.f);
    const ImageError plain = compare_images(run(s, 64, 0, 5).film, ref, &mask);
    // Through the renderer's keys, as a scene sets them: guided paths take no roulette by
    // default.
    s.renderer.set("guided", "true", "test", 0);
    s.renderer.set("guide_emitted", "200000", "test", 0);
    s.render = render_settings(s);
    s.set_resolution(64, 64);
    REQUIRE(s.render.guide.enabled);
    CHECK(s.render.rr_depth > s.render.max_depth);
    const RenderResult guided_run = run(s, 64, 0, 5);
    const ImageError guided = compare_images(guided_run.film, ref, &mask);
    INFO("rmse plain " << plain.rmse << " guided " << guided.rmse << "; means " << plain.mean_a.g
                       << " " << guided.mean_a.g << " ref " << guided.mean_b.g);
    CHECK(guided.mean_a.r == Approx(guided.mean_b.r).epsilon(0.02));
    CHECK(guided.mean_a.g == Approx(guided.mean_b.g).epsilon(0.02));
    CHECK(guided.mean_a.b == Approx(guided.mean_b.b).epsilon(0.02));
    // Measured 0.030 against 0.052.
    CHECK(guided.rmse < 0.75 * plain.rmse);

    // Bit-identical for any thread count: the guide is built in photon order.
    s.set_resolution(24, 24);
    CHECK(compare_images(run(s, 4, 1, 9).film, run(s, 4, 2, 9).film).max_abs == 0.0);
}

TEST_CASE("guided path settings: path only, keys need guided=true", "[guide][fast]") {
    auto settings = [](const std::string& attrs) {
        const std::string xml = R"(<scene><objects><sphere radius="1"><center x="0" y="0" z="5"/>
            <material type="lambert"/></sphere></objects><film width="8" height="8"/>
            <renderer )" + attrs +
                                R"(/>
            <camera><eye x="0" y="0" z="0"/><target x="0" y="0" z="1"/></camera></scene>)";
        return TestScene(parse_scene(xml, "guide.xml", ".")).render;
    };
    const RenderSettings ok = settings(
        R"(type="path" guided="true" guide_fraction="0.3" guide_cells="16" guide_emitted="5000")");
    CHECK(ok.guide.enabled);
    CHECK(ok.guide.fraction == Approx(0.3f));
    CHECK(ok.guide.cells == 16);
    CHECK(ok.guide.emitted == 5000);
    CHECK(ok.rr_depth > ok.max_depth);  // no roulette unless asked for
    CHECK(settings(R"(type="path" guided="true" rr_depth="4")").rr_depth == 4);
    CHECK(settings(R"(type="path")").rr_depth == 3);
    // Guiding belongs to path: under photon mapping a warning, and no guide.
    CHECK_FALSE(settings(R"(type="photon" guided="true")").guide.enabled);
    CHECK_THAT(settings(R"(type="photon" guided="true")").warnings.at(0),
               Catch::Contains("guided applies to type=\"path\""));
    CHECK_THROWS_WITH(settings(R"(type="path" guide_fraction="0.3")"),
                      Catch::Contains("guide_fraction needs guided=true"));
    CHECK_THROWS_WITH(settings(R"(type="path" guided="true" guide_fraction="1")"),
                      Catch::Contains("guide_fraction"));
    CHECK_THROWS_WITH(settings(R"(type="path" guided="true" indirect="irradiance_cache")"),
                      Catch::Contains("do not combine"));
}
