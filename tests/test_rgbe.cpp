// Ward's shared-exponent colour (core/rgbe.h) and the photon map that stores its power and
// precomputed irradiance with it (compact_power, the photon thesis' 6.5).
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "engine/core/rgbe.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/photon/photon_map.h"
#include "test_util.h"

using namespace foton;

TEST_CASE("RGBE keeps 8 significant bits of the largest channel", "[rgbe]") {
    std::mt19937 gen(7);
    std::uniform_real_distribution<float> unit(0.f, 1.f);
    std::uniform_real_distribution<float> exponent(-60.f, 60.f);
    for (int i = 0; i < 100000; ++i) {
        const float scale = std::exp2(exponent(gen));
        const RGB c{unit(gen) * scale, unit(gen) * scale, unit(gen) * scale};
        const RGB d = decode_rgbe(encode_rgbe(c));
        const float big = std::max(c.r, std::max(c.g, c.b));
        // Each channel within half a step of the largest channel's 8-bit mantissa (a step is
        // at most 2^-7 of it), or, below one step, dark.
        for (int k = 0; k < 3; ++k) {
            const float a = (&c.r)[k], b = (&d.r)[k];
            INFO(a << " -> " << b << " (largest " << big << ")");
            if (b > 0.f)
                CHECK(std::fabs(a - b) <= big * std::exp2(-8.f));
            else
                CHECK(a < big * std::exp2(-7.f));
        }
        CHECK(std::fabs(std::max(d.r, std::max(d.g, d.b)) - big) <= big * std::exp2(-8.f));
    }
    CHECK(encode_rgbe(RGB{0.f}) == 0u);
    CHECK(decode_rgbe(0u).r == 0.f);
    // Negative and NaN channels are no light; beyond the exponent's range it saturates.
    CHECK(decode_rgbe(encode_rgbe(RGB{-1.f, NAN, 2.f})).r == 0.f);
    CHECK(decode_rgbe(encode_rgbe(RGB{-1.f, NAN, 2.f})).b == Approx(2.f).epsilon(1.f / 256));
    CHECK(std::isfinite(decode_rgbe(encode_rgbe(RGB{3e38f})).g));
    // A mean of many encoded values is unbiased where the steps are not zero (the decoder
    // takes each step's centre).
    double sum = 0.0, sum_d = 0.0;
    for (int i = 0; i < 100000; ++i) {
        const RGB c{1.f, 0.01f + 0.99f * unit(gen), 0.5f};
        sum += c.g;
        sum_d += decode_rgbe(encode_rgbe(c)).g;
    }
    CHECK(sum_d / sum == Approx(1.0).epsilon(2e-4));
}

TEST_CASE("compact photon power: 8 bytes less a photon, the same estimates", "[rgbe][photon]") {
    std::mt19937 gen(3);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    PhotonMap a;
    for (int i = 0; i < 20000; ++i) {
        const Vec3 p{u(gen), 0.f, u(gen)};
        a.push(p, RGB{u(gen), u(gen), u(gen)} * 1e-3f, Vec3{0, 1, 0}, Vec3{0, 1, 0}, 0);
    }
    PhotonMap b = a;
    b.compact_power();
    a.build();
    b.build();
    CHECK(b.compact());
    CHECK(a.memory_bytes() - b.memory_bytes() == 8 * a.size());
    CHECK(b.total_power().r == Approx(a.total_power().r).epsilon(1e-3));
    EstimateParams params;
    params.k = 200;
    params.max_radius = 0.2f;
    const auto parallel = [](std::size_t n,
                             const std::function<void(std::size_t, std::size_t)>& f) { f(0, n); };
    a.precompute_irradiance(4, params, parallel);
    b.precompute_irradiance(4, params, parallel);
    CHECK(b.precomputed_size() == a.precomputed_size());
    for (float x : {0.3f, 0.5f, 0.7f})
        for (float z : {0.3f, 0.6f}) {
            const RGB ea = a.irradiance({x, 0.f, z}, {0, 1, 0}, params);
            const RGB eb = b.irradiance({x, 0.f, z}, {0, 1, 0}, params);
            CHECK(eb.g == Approx(ea.g).epsilon(5e-3));
            RGB pa, pb;
            REQUIRE(a.lookup_irradiance({x, 0.f, z}, {0, 1, 0}, 0.2f, pa));
            REQUIRE(b.lookup_irradiance({x, 0.f, z}, {0, 1, 0}, 0.2f, pb));
            CHECK(std::fabs(pb.b - pa.b) <= std::max(pa.r, std::max(pa.g, pa.b)) / 256.f);
        }
    CHECK_THROWS_AS(b.push({}, RGB{1.f}, {0, 1, 0}, {0, 1, 0}, 0), std::logic_error);
}

TEST_CASE("compact_power renders photon mapping's image within RGBE's error", "[rgbe][photon]") {
    for (const char* type : {"photon", "sppm"}) {
        CAPTURE(type);
        RendererOverrides set{{"type", type},
                              {"global_photons", "40000"},
                              {"caustic_photons", "20000"},
                              {"gather_rays", "8"},
                              {"photons_per_pass", "20000"}};
        TestScene s = load_scene(test::source_path("scenes/cornell-caustics.xml"), set);
        s.set_resolution(32, 32);
        s.render = render_settings(s);
        const RenderResult full = render_test(s, 2, 2);
        s.render.photon.compact_power = true;
        const RenderResult compact = render_test(s, 2, 2);
        double sa = 0.0, sb = 0.0, diff = 0.0;
        for (std::size_t p = 0; p < full.film.pixels.size(); ++p) {
            sa += full.film.pixels[p].g;
            sb += compact.film.pixels[p].g;
            diff += std::fabs(full.film.pixels[p].g - compact.film.pixels[p].g);
        }
        // The same photons, each power rounded by at most 1/256 of its largest channel.
        CHECK(sb / sa == Approx(1.0).epsilon(2e-3));
        CHECK(diff / sa < 5e-3);
        CHECK(diff > 0.0);  // it did store them compactly
    }
}
