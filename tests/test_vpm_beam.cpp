// The beam radiance estimate (vpm estimator="beam"): the photon discs' BVH finds exactly the
// photons within r of a segment, the segment transmittance is unbiased in grid media, and the
// estimate converges to volpath's image on the foggy box and the smoke grid.
#include <catch2/catch.hpp>
#include <cmath>
#include <set>
#include <string>

#include "engine/core/rng.h"
#include "engine/transport/volume/beam_estimate.h"
#include "media_util.h"
#include "test_util.h"

using namespace foton;
using test::image_mean;
using test::masked_mean;

TEST_CASE("photon discs: a segment's query finds exactly the photons within r of it",
          "[media][fast]") {
    PhotonMap map;
    for (uint64_t i = 0; i < 3000; ++i)
        map.push({rng::uniform(4, 1, i, 0) * 10.f, rng::uniform(4, 1, i, 1) * 10.f,
                  rng::uniform(4, 1, i, 2) * 10.f},
                 RGB{1.f}, {0, 0, 1}, {0, 0, 1}, 0, 0);
    map.build();
    PhotonDiscs discs;
    const float r = 0.4f;
    discs.build(map, r, {});
    uint64_t found_total = 0;
    for (uint64_t k = 0; k < 200; ++k) {
        const Vec3 o{rng::uniform(4, 2, k, 0) * 12.f - 1.f, rng::uniform(4, 2, k, 1) * 12.f - 1.f,
                     rng::uniform(4, 2, k, 2) * 12.f - 1.f};
        const Vec3 d =
            normalize(Vec3{rng::uniform(4, 2, k, 3) - 0.5f, rng::uniform(4, 2, k, 4) - 0.5f,
                           rng::uniform(4, 2, k, 5) - 0.5f});
        const float t_end = k % 3 == 0 ? kInfinity : 2.f + 10.f * rng::uniform(4, 2, k, 6);
        std::set<uint32_t> expected, found;
        for (uint32_t i = 0; i < map.size(); ++i) {
            const Vec3 v = map.position(i) - o;
            const float t = dot(v, d);
            if (t >= 0.f && t < t_end && length_squared(v - d * t) < r * r) expected.insert(i);
        }
        discs.along(o, d, t_end, [&](uint32_t i, float t, float dist2) {
            CHECK(std::fabs(t - dot(map.position(i) - o, d)) < 1e-4f);
            CHECK(dist2 < r * r);
            found.insert(i);
        });
        CHECK(found == expected);
        found_total += found.size();
    }
    CHECK(found_total > 500);
}

TEST_CASE("beam estimate: a grid segment's transmittance is unbiased at every t", "[media][fast]") {
    // An uneven 8^3 cloud over [-1, 1]^3, grey coefficients.
    std::vector<float> v;
    for (int i = 0; i < 512; ++i) v.push_back(0.5f + 1.5f * rng::uniform(4, 3, uint64_t(i), 0));
    Bounds3 box;
    box.extend(Vec3{-1, -1, -1});
    box.extend(Vec3{1, 1, 1});
    Medium m;
    m.kind = MediumKind::Grid;
    m.sigma_a = RGB{0.5f};
    m.sigma_s = RGB{1.f};
    m.density = std::make_shared<const DensityGrid>(8, 8, 8, v, box);
    const Vec3 o{-1.5f, 0.2f, -0.1f}, d = normalize(Vec3{1.f, 0.1f, 0.05f});
    const float ts[3] = {0.8f, 1.6f, 2.4f};
    double tau[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k)
        for (int i = 0; i < 20000; ++i) {
            const float t = (i + 0.5f) * ts[k] / 20000.f;
            tau[k] += m.at(o + d * t).sigma_a.r * 3.f * ts[k] / 20000.f;  // sigma_t = 3 sigma_a
        }
    SegmentTransmittance tr;
    double mean[3] = {0, 0, 0};
    const int n = 50000;
    for (int i = 0; i < n; ++i) {
        uint64_t draws = 0;
        auto u = [&] { return rng::uniform(4, 4, uint64_t(i), draws++); };
        tr.walk(m, o, d, 3.f, u);
        for (int k = 0; k < 3; ++k) mean[k] += tr.at(ts[k]).r;
    }
    for (int k = 0; k < 3; ++k) {
        INFO("t " << ts[k] << ": exact " << std::exp(-tau[k]) << ", mean " << mean[k] / n);
        CHECK(mean[k] / n == Approx(std::exp(-tau[k])).margin(0.01));
    }
}

TEST_CASE("vpm's beam estimate converges to volpath's image: the foggy box and the smoke grid",
          "[media][render]") {
    const uint32_t e = test::effort();
    TestScene s = test::fog(24);
    s.render.integrator = "volpath";
    const Film volpath = render_test(s, 1024 * e, 2, 3).film;
    const RGB ref = masked_mean(volpath, volpath);
    TestScene v =
        load_scene(test::source_path("scenes/cornell-fog.xml"),
                   {{"type", "vpm"}, {"photons_per_pass", "20000"}, {"estimator", "beam"}});
    v.set_resolution(24, 24);
    const RGB got = masked_mean(render_test(v, 48 * e, 2, 3).film, volpath);
    INFO("fog: volpath " << ref.r << " " << ref.g << " " << ref.b << ", beam " << got.r << " "
                         << got.g << " " << got.b);
    CHECK(got.r == Approx(ref.r).epsilon(0.04));
    CHECK(got.g == Approx(ref.g).epsilon(0.04));
    CHECK(got.b == Approx(ref.b).epsilon(0.04));
    CHECK(render_test(v, 2, 1, 4).film.pixels == render_test(v, 2, 3, 4).film.pixels);
    TestScene g = load_scene(test::source_path("scenes/smoke.xml"));
    g.set_resolution(24, 24);
    g.render.integrator = "volpath";
    const RGB gref = image_mean(render_test(g, 256 * e, 2, 3).film);
    TestScene b =
        load_scene(test::source_path("scenes/smoke.xml"),
                   {{"type", "vpm"}, {"photons_per_pass", "20000"}, {"estimator", "beam"}});
    b.set_resolution(24, 24);
    const RGB gb = image_mean(render_test(b, 32 * e, 2, 3).film);
    INFO("smoke: volpath " << gref.r << " " << gref.g << " " << gref.b << ", beam " << gb.r << " "
                           << gb.g << " " << gb.b);
    CHECK(gb.r == Approx(gref.r).epsilon(0.03));
    CHECK(gb.g == Approx(gref.g).epsilon(0.03));
    CHECK(gb.b == Approx(gref.b).epsilon(0.03));
}
