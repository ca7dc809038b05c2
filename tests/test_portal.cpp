// Portal environment lights and several infinite lights (scene/environment.h): the windowed
// density they sample, the portal's window against the rectangle's geometry, and renders
// that a portal must leave unchanged.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "engine/core/error.h"
#include "engine/core/rng.h"
#include "engine/core/warp.h"
#include "engine/core/windowed_distribution.h"
#include "engine/film/metrics.h"
#include "engine/scene/environment.h"
#include "engine/scene/pbrt_loader.h"
#include "engine/scene/xml_loader.h"
#include "test_util.h"

using namespace foton;

TEST_CASE("portal: the windowed density samples in proportion within any window",
          "[portal][fast]") {
    const int nu = 7, nv = 5;
    std::vector<float> f(nu * nv);
    for (int i = 0; i < nu * nv; ++i) f[std::size_t(i)] = i % 6 == 0 ? 0.f : 0.5f + float(i % 4);
    const WindowedDistribution d(f, nu, nv);
    for (const Window2 w :
         {Window2{}, Window2{0.1f, 0.25f, 0.83f, 0.9f}, Window2{0.3f, 0.3f, 0.35f, 0.7f}}) {
        INFO("window " << w.u0 << " " << w.v0 << " " << w.u1 << " " << w.v1);
        // The expected share of each cell: f times the cell's area inside the window.
        std::vector<double> expect(f.size(), 0.0), got(f.size(), 0.0);
        double total = 0.0;
        for (int y = 0; y < nv; ++y)
            for (int x = 0; x < nu; ++x) {
                const double ox = std::max(0.0, std::min<double>(w.u1, (x + 1.0) / nu) -
                                                    std::max<double>(w.u0, double(x) / nu));
                const double oy = std::max(0.0, std::min<double>(w.v1, (y + 1.0) / nv) -
                                                    std::max<double>(w.v0, double(y) / nv));
                expect[std::size_t(y * nu + x)] = f[std::size_t(y * nu + x)] * ox * oy;
                total += expect[std::size_t(y * nu + x)];
            }
        CHECK(d.integral(w) == Approx(total).epsilon(1e-9));
        const int n = 200000;
        for (int i = 0; i < n; ++i) {
            Point2 p;
            float pdf;
            REQUIRE(
                d.sample({rng::uniform(3, 1, uint64_t(i), 0), rng::uniform(3, 1, uint64_t(i), 1)},
                         w, p, pdf));
            REQUIRE(w.contains(p));
            REQUIRE(pdf == Approx(d.pdf(p, w)).epsilon(1e-4));
            const int x = std::min(int(p.x * nu), nu - 1), y = std::min(int(p.y * nv), nv - 1);
            got[std::size_t(y * nu + x)] += 1.0;
        }
        for (std::size_t c = 0; c < f.size(); ++c) {
            const double e = expect[c] / total * n;
            if (e < 1.0) {
                CHECK(got[c] <= 2.0 + e * 3.0);
                continue;
            }
            CHECK(std::fabs(got[c] - e) < 5.0 * std::sqrt(e) + 1.0);
        }
    }
    CHECK(d.pdf({0.9f, 0.9f}, Window2{0.1f, 0.1f, 0.5f, 0.5f}) == 0.f);
}

namespace {

// An equal-area map whose radiance varies smoothly over the sphere.
TextureImage gradient_map(int n) {
    TextureImage m;
    m.width = m.height = n;
    m.path = "gradient";
    m.texels.resize(std::size_t(n * n));
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const Vec3 d = equal_area_square_to_sphere({(x + 0.5f) / n, (y + 0.5f) / n});
            m.texels[std::size_t(y * n + x)] = RGB{1.f + d.x, 1.5f + d.y, 1.2f + d.z};
        }
    return m;
}

Vec3 random_direction(uint64_t i) {
    return warp::uniform_sphere({rng::uniform(9, 2, i, 0), rng::uniform(9, 2, i, 1)});
}

}  // namespace

TEST_CASE("portal: light arrives through the rectangle only, sampled there with its density",
          "[portal][fast]") {
    // A window 2 wide and 1 high in the plane x = 4, light from +x.
    const Vec3 c[4] = {{4, 1, 1}, {4, 1, 2}, {4, 3, 2}, {4, 3, 1}};
    const TextureImage map = gradient_map(32);
    const Environment portal = Environment::portal(map, RGB{2.f}, {0, 0, 1}, {1, 0, 0}, c);
    const Environment open =
        Environment::image(map, EnvMapping::EqualArea, RGB{2.f}, {0, 0, 1}, {1, 0, 0});
    REQUIRE(portal.has_portal());
    const EnvLayer& l = portal.layers()[0];
    const Vec3 p{1.f, 1.5f, 0.8f};
    int through = 0;
    double pdf_mean = 0.0;
    const int n = 100000;
    for (int i = 0; i < n; ++i) {
        const Vec3 w = random_direction(uint64_t(i));
        const RGB L = portal.Le(p, w);
        const bool crosses = l.crosses_portal(p, w);
        REQUIRE(crosses == !L.is_black());
        if (crosses) {
            ++through;
            // The rectified map holds the open map's light (nearest texels of both: close).
            CHECK(L.g == Approx(open.Le(p, w).g).epsilon(0.08));
        }
        pdf_mean += double(portal.pdf(p, w)) / warp::kUniformSpherePdf / n;
    }
    CHECK(through > 100);
    // The density integrates to one over the directions through the window.
    CHECK(pdf_mean == Approx(1.0).epsilon(0.05));
    for (int i = 0; i < 2000; ++i) {
        float pdf = 0.f;
        const Vec3 w = portal.sample(
            p, {rng::uniform(4, 1, uint64_t(i), 0), rng::uniform(4, 1, uint64_t(i), 1)}, pdf);
        REQUIRE(pdf > 0.f);
        CHECK(l.crosses_portal(p, w));
        CHECK(pdf == Approx(portal.pdf(p, w)).epsilon(1e-3));
    }
    // From outside (in front of the window) nothing comes through it.
    CHECK(portal.Le({5, 2, 1.5f}, {1, 0, 0}).is_black());
    const Vec3 skew[4] = {{4, 1, 1}, {4, 1, 2}, {4, 3, 2.5f}, {4, 3, 1}};
    CHECK_THROWS_AS(Environment::portal(map, RGB{1.f}, {0, 0, 1}, {1, 0, 0}, skew), InputError);
}

namespace {

// The room of scenes/pbrt/portal/room.pbrt with one window (the other closed) under one sky,
// with or without the portal, small.
std::string room(bool portal) {
    std::string s = R"(LookAt 0.4 0.4 1.6  3 3 0.6  0 0 1
Camera "perspective" "float fov" 70
Film "rgb" "integer xresolution" 24 "integer yresolution" 16
Integrator "path" "integer maxdepth" 5
WorldBegin
LightSource "infinite" "rgb L" [4 3 2])";
    if (portal) s += R"( "point3 portal" [4 1.5 1  4 1.5 2  4 2.5 2  4 2.5 1])";
    s += R"(
Material "diffuse" "rgb reflectance" [0.6 0.6 0.6]
Shape "trianglemesh" "point3 P" [0 0 0  4 0 0  4 4 0  0 4 0  0 0 3  0 4 3  4 4 3  4 0 3
  0 0 0  0 4 0  0 4 3  0 0 3  0 0 0  0 0 3  4 0 3  4 0 0  0 4 0  0 4 3  4 4 3  4 4 0
  4 0 0  4 4 0  4 4 1  4 0 1  4 0 2  4 4 2  4 4 3  4 0 3  4 0 1  4 1.5 1  4 1.5 2  4 0 2
  4 2.5 1  4 4 1  4 4 2  4 2.5 2]
  "integer indices" [0 1 2 0 2 3  4 5 6 4 6 7  8 9 10 8 10 11  12 13 14 12 14 15  16 17 18 16 18 19
  20 21 22 20 22 23  24 25 26 24 26 27  28 29 30 28 30 31  32 33 34 32 34 35]
)";
    return s;
}

}  // namespace

TEST_CASE("portal: a window's portal changes the noise, not the image, and skies add up",
          "[portal][render]") {
    TestScene with(parse_pbrt_scene(room(true), "room.pbrt", "."));
    TestScene without(parse_pbrt_scene(room(false), "room.pbrt", "."));
    const ImageError e =
        compare_images(render_test(with, 1024, 0, 1).film, render_test(without, 4096, 0, 2).film);
    INFO("portal " << e.mean_a.g << " open " << e.mean_b.g);
    CHECK(e.mean_a.r == Approx(e.mean_b.r).epsilon(0.01));
    CHECK(e.mean_a.g == Approx(e.mean_b.g).epsilon(0.01));
    CHECK(e.mean_a.b == Approx(e.mean_b.b).epsilon(0.01));
    // Two infinite lights are their sum; the bidirectional integrators refuse a portal.
    const Scene two = parse_pbrt_scene(R"(Camera "perspective"
WorldBegin
LightSource "infinite" "rgb L" [1 2 3]
LightSource "infinite" "rgb L" [0.5 0.5 0.5]
Shape "sphere")",
                                       "two.pbrt", ".");
    REQUIRE(two.environment->layers().size() == 2);
    CHECK(two.environment->Le({}, {0, 0, 1}).b == Approx(3.5f));
    CHECK(two.environment->pdf({}, {1, 0, 0}) == Approx(warp::kUniformSpherePdf));
    // The XML's environments add up too, a portal among them.
    const Scene xml = parse_scene(R"(<scene><lights>
  <environment intensity="2"/>
  <environment intensity="3"><color r="1" g="0" b="0"/><portal><corner x="4" y="1" z="1"/>
    <corner x="4" y="1" z="2"/><corner x="4" y="3" z="2"/><corner x="4" y="3" z="1"/></portal>
  </environment></lights>
  <objects><sphere radius="0.1"><center x="0" y="0" z="0"/><material type="lambert"/></sphere></objects>
  <film width="4" height="4"/>
  <camera><eye x="0" y="0" z="5"/><target x="0" y="0" z="0"/><up x="0" y="1" z="0"/></camera>
</scene>)",
                                  "sky.xml", ".");
    REQUIRE(xml.environment->layers().size() == 2);
    CHECK(xml.environment->Le({1.f, 1.5f, 0.8f}, {1, 0, 0.2f}).r == Approx(5.f));
    CHECK(xml.environment->Le({1.f, 1.5f, 0.8f}, {-1, 0, 0}).r == Approx(2.f));
    with.render.integrator = "bdpt";
    CHECK_THROWS_AS(render_test(with, 1), InputError);
}
