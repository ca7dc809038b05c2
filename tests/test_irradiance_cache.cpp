// The irradiance cache: weights and octree lookups against the brute-force scan, the
// record's irradiance and gradients against analytic values for a square light over a
// plane, and the cache inside the photon mapper against plain final gathering.
#include <catch2/catch.hpp>

#include <cmath>

#include "engine/accel/intersector.h"
#include "engine/core/rng.h"
#include "engine/film/metrics.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/irradiance_cache/irradiance_cache.h"
#include "engine/transport/registry/render.h"
#include "test_util.h"

using namespace foton;

namespace {

// Irradiance at p (normal n) from a Lambertian polygon of radiance L (Lambert's formula).
double polygon_irradiance(const std::vector<Vec3>& q, const Vec3& p, const Vec3& n, double L) {
    double sum = 0.0;
    for (std::size_t i = 0; i < q.size(); ++i) {
        const Vec3 a = normalize(q[i] - p), b = normalize(q[(i + 1) % q.size()] - p);
        const double angle = std::acos(std::clamp(double(dot(a, b)), -1.0, 1.0));
        const Vec3 c = normalize(cross(a, b));
        sum += angle * double(dot(n, c));
    }
    return 0.5 * L * std::fabs(sum);
}

// A record at p on the plane z = 0 (normal n) seeing a horizontal light at height h: each
// stratum's ray either hits the light where inside(x, y) holds (radiance L, distance t) or
// escapes.
template <class Inside>
IrradianceRecord plane_light_record(const Vec3& p, const Vec3& n, Inside&& inside, float h, float L,
                                    uint32_t samples, uint64_t seed, float r_min = 0.f,
                                    float r_max = kInfinity) {
    const HemisphereStrata strata = HemisphereStrata::from_count(samples);
    Vec3 s, t;
    orthonormal_basis(n, s, t);
    std::vector<RGB> radiance(strata.count(), RGB{0.f});
    std::vector<float> dist(strata.count(), kInfinity);
    for (uint32_t j = 0; j < strata.m; ++j)
        for (uint32_t k = 0; k < strata.n; ++k) {
            const uint32_t i = j * strata.n + k;
            const Vec3 l =
                strata.direction(j, k, {rng::uniform(seed, 1, i, 0), rng::uniform(seed, 1, i, 1)});
            const Vec3 w = s * l.x + t * l.y + n * l.z;
            if (w.z <= 0.f) continue;
            const float tt = (h - p.z) / w.z;
            const Vec3 x = p + w * tt;
            if (inside(x.x, x.y)) {
                radiance[i] = RGB{L};
                dist[i] = tt;
            }
        }
    return build_record(p, s, t, n, strata, radiance.data(), dist.data(), RadiusRule::Harmonic,
                        r_min, r_max);
}

IrradianceRecord square_light_record(const Vec3& p, const Vec3& n, float half, float h, float L,
                                     uint32_t samples, uint64_t seed) {
    return plane_light_record(
        p, n, [&](float x, float y) { return std::fabs(x) < half && std::fabs(y) < half; }, h, L,
        samples, seed);
}

// Irradiance on the plane z = 0 at distance r from the axis of a disc of radius a and
// radiance L at height h, parallel to it.
double disc_irradiance(double r, double a, double h, double L) {
    const double q = h * h + r * r + a * a;
    return 0.5 * kPi * L * (1.0 - (h * h + r * r - a * a) / std::sqrt(q * q - 4.0 * r * r * a * a));
}

}  // namespace

TEST_CASE("an irradiance record matches the analytic irradiance and gradients of a square light",
          "[cache]") {
    const float half = 1.f, h = 1.f, L = 1.f;
    const std::vector<Vec3> square = {
        {-half, -half, h}, {half, -half, h}, {half, half, h}, {-half, half, h}};
    for (const Vec3 p : {Vec3{0.f, 0.f, 0.f}, Vec3{0.8f, 0.3f, 0.f}, Vec3{1.5f, -0.5f, 0.f}}) {
        const Vec3 n{0.f, 0.f, 1.f};
        const IrradianceRecord r = square_light_record(p, n, half, h, L, 20000, 7);
        const double e = polygon_irradiance(square, p, n, L);
        // dE/dx, dE/dy by central differences of the analytic irradiance.
        const float dx = 1e-3f;
        const double gx = (polygon_irradiance(square, p + Vec3{dx, 0, 0}, n, L) -
                           polygon_irradiance(square, p - Vec3{dx, 0, 0}, n, L)) /
                          (2 * dx);
        const double gy = (polygon_irradiance(square, p + Vec3{0, dx, 0}, n, L) -
                           polygon_irradiance(square, p - Vec3{0, dx, 0}, n, L)) /
                          (2 * dx);
        // Rotation about the x and y axes: the normal tilts, dE/d angle.
        const float da = 1e-3f;
        auto tilted = [&](const Vec3& axis, float a) {
            // Rodrigues for n = z about a unit axis in the plane.
            return normalize(n * std::cos(a) + cross(axis, n) * std::sin(a));
        };
        const double rx = (polygon_irradiance(square, p, tilted({1, 0, 0}, da), L) -
                           polygon_irradiance(square, p, tilted({1, 0, 0}, -da), L)) /
                          (2 * da);
        const double ry = (polygon_irradiance(square, p, tilted({0, 1, 0}, da), L) -
                           polygon_irradiance(square, p, tilted({0, 1, 0}, -da), L)) /
                          (2 * da);
        INFO("p " << p.x << " " << p.y << ": E " << r.e.g << " vs " << e << "; grad_t "
                  << r.grad_t[1].x << " " << r.grad_t[1].y << " vs " << gx << " " << gy
                  << "; grad_r " << r.grad_r[1].x << " " << r.grad_r[1].y << " vs " << rx << " "
                  << ry);
        const double scale = std::max(std::fabs(gx), std::fabs(gy));
        CHECK(r.e.g == Approx(e).epsilon(0.01));
        CHECK(r.grad_t[1].x == Approx(gx).margin(0.1 * scale + 0.01 * e));
        CHECK(r.grad_t[1].y == Approx(gy).margin(0.1 * scale + 0.01 * e));
        const double rscale = std::max(std::fabs(rx), std::fabs(ry));
        CHECK(r.grad_r[1].x == Approx(rx).margin(0.05 * rscale + 0.01 * e));
        CHECK(r.grad_r[1].y == Approx(ry).margin(0.05 * rscale + 0.01 * e));
        CHECK(r.grad_t[1].z == Approx(0.f).margin(1e-6));
    }
}

TEST_CASE("octree lookups equal the brute-force scan for both weights", "[cache]") {
    // Records on the faces of a unit box and a sphere, radii over two orders of magnitude.
    Bounds3 b;
    b.extend({-1.f, -1.f, -1.f});
    b.extend({1.f, 1.f, 1.f});
    for (CacheWeight kind : {CacheWeight::Notes, CacheWeight::Ward}) {
        CacheParams params;
        params.weight = kind;
        IrradianceCache cache(b, params);
        auto surface = [](uint64_t i, uint64_t stream, Vec3& p, Vec3& n) {
            const float u = rng::uniform(9, stream, i, 0), v = rng::uniform(9, stream, i, 1);
            const int face = int(rng::uniform(9, stream, i, 2) * 4.f);
            if (face == 3) {  // the sphere of radius 0.5
                n = normalize(Vec3{u - 0.5f, v - 0.5f, rng::uniform(9, stream, i, 3) - 0.5f});
                p = n * 0.5f;
                return;
            }
            const float s = 2.f * u - 1.f, t = 2.f * v - 1.f;
            p = face == 0 ? Vec3{s, -1.f, t} : face == 1 ? Vec3{-1.f, s, t} : Vec3{s, t, 1.f};
            n = face == 0 ? Vec3{0, 1, 0} : face == 1 ? Vec3{1, 0, 0} : Vec3{0, 0, -1};
        };
        for (uint64_t i = 0; i < 3000; ++i) {
            IrradianceRecord r;
            surface(i, 1, r.p, r.n);
            r.r_harmonic = 0.005f * std::pow(40.f, rng::uniform(9, 2, i, 0));
            r.r_min = 0.01f;
            r.r_max = 0.15f;
            r.r = std::clamp(r.r_harmonic, r.r_min, r.r_max);
            r.e = RGB(rng::uniform(9, 3, i, 0), 0.5f, 1.f);
            for (int c = 0; c < 3; ++c) {
                r.grad_t[c] = Vec3{0.1f, -0.2f, 0.05f} * float(c);
                r.grad_r[c] = Vec3{0.02f, 0.01f, -0.03f};
            }
            cache.insert(r);
        }
        CacheCounters tree_st, scan_st;
        int found = 0;
        const auto always = [](const IrradianceRecord&) { return true; };
        for (uint64_t q = 0; q < 2000; ++q) {
            Vec3 p, n;
            surface(q, 4, p, n);
            RGB e_tree, e_scan;
            const bool a = cache.interpolate(p, n, e_tree, always, tree_st);
            const bool c = cache.interpolate_brute(p, n, e_scan, always, scan_st);
            REQUIRE(a == c);
            found += a;
            // The same records summed in the same order: identical to the bit.
            CHECK(e_tree.r == e_scan.r);
            CHECK(e_tree.g == e_scan.g);
            CHECK(e_tree.b == e_scan.b);
        }
        INFO("interpolated " << found << " of 2000; candidates per lookup: octree "
                             << double(tree_st.candidates) / 2000 << ", scan "
                             << double(scan_st.candidates) / 2000);
        CHECK(tree_st.used == scan_st.used);
        CHECK(found > 200);
        CHECK(found < 2000);
        // The tree looks at a small fraction of the records.
        CHECK(tree_st.candidates * 10 < scan_st.candidates);
    }
}

TEST_CASE("the notes' weight: zero at the validity limit and beyond 10 degrees", "[cache]") {
    CacheParams params;  // notes, kappa 1
    IrradianceRecord r;
    r.p = {0, 0, 0};
    r.n = {0, 0, 1};
    r.r_harmonic = 1.f;
    r.r_min = 0.5f;
    r.r_max = 10.f;
    r.r = 1.f;
    // clamp(2 R, R_min, R_max) = 2: w = 1 - d / 2 on the plane.
    CHECK(record_weight(params, r, {1.f, 0, 0}, r.n) == Approx(0.5f));
    CHECK(record_weight(params, r, {0, 1.99f, 0}, r.n) == Approx(0.005f).margin(1e-4));
    CHECK(record_weight(params, r, {0, 2.01f, 0}, r.n) == 0.f);
    CHECK(record_influence(params, r) == Approx(2.f));
    // 9 and 11 degrees of normal difference at the record's position.
    const float a9 = 9.f * kPi / 180.f, a11 = 11.f * kPi / 180.f;
    CHECK(record_weight(params, r, r.p, {std::sin(a9), 0, std::cos(a9)}) > 0.f);
    CHECK(record_weight(params, r, r.p, {std::sin(a11), 0, std::cos(a11)}) == 0.f);
    // Ward's: w = 1 / (d / R + sqrt(1 - n.n_i)) used while above 1 / a.
    params.weight = CacheWeight::Ward;
    params.a = 0.3f;
    CHECK(record_weight(params, r, {0.2f, 0, 0}, r.n) == Approx(5.f));
    CHECK(record_weight(params, r, {0.31f, 0, 0}, r.n) == 0.f);
    CHECK(record_influence(params, r) == Approx(0.3f));
}

TEST_CASE("the irradiance cache renders the closed diffuse box like plain final gathering",
          "[cache][photon]") {
    TestScene s = load_scene(test::source_path("scenes/cornell-diffuse.xml"));
    s.set_resolution(64, 64);
    s.render.integrator = "photon";
    s.render.photon.global_photons = 100000;
    s.render.photon.caustic_photons = 0;
    const auto acc = make_intersector(s, s.accel);
    RenderOptions opt;
    opt.spp = 2;
    s.render.photon.gather_rays = 512;
    const RenderResult fg = render(s, s.render, *acc, opt);
    s.render.indirect = IndirectMode::IrradianceCache;
    s.render.cache.samples = 1024;
    const RenderResult ic = render(s, s.render, *acc, opt);
    const ImageError e = compare_images(ic.film, fg.film);
    INFO("records " << ic.stats.cache_stored << ", lookups " << ic.stats.cache.lookups << ", rmse "
                    << e.rmse << ", means " << e.mean_a.g << " " << e.mean_b.g);
    CHECK(ic.stats.cache_stored > 50);
    CHECK(ic.stats.cache_stored < 64 * 64 / 4);
    CHECK(ic.stats.cache.interpolated > ic.stats.cache.lookups * 9 / 10);
    CHECK(e.mean_a.r == Approx(e.mean_b.r).epsilon(0.02));
    CHECK(e.mean_a.g == Approx(e.mean_b.g).epsilon(0.02));
    CHECK(e.mean_a.b == Approx(e.mean_b.b).epsilon(0.02));
    CHECK(e.rmse < 0.01);
    // Deterministic for any thread count: the fill's passes merge in a fixed order.
    opt.threads = 1;
    const Film one = render(s, s.render, *acc, opt).film;
    opt.threads = 2;
    CHECK(compare_images(one, render(s, s.render, *acc, opt).film).max_abs == 0.0);
}

TEST_CASE(
    "on a plane under an emitting disc, the translation gradient is dE/dr and helps "
    "interpolation",
    "[cache]") {
    const float a = 1.f, h = 1.f, L = 1.f;
    auto in_disc = [&](float x, float y) { return x * x + y * y < a * a; };
    const Vec3 up{0.f, 0.f, 1.f};
    for (const float r : {0.3f, 0.9f, 1.5f, 2.2f}) {
        const IrradianceRecord rec = plane_light_record({r, 0.f, 0.f}, up, in_disc, h, L, 20000, 3);
        const double e = disc_irradiance(r, a, h, L);
        const double dr = 1e-3;
        const double de =
            (disc_irradiance(r + dr, a, h, L) - disc_irradiance(r - dr, a, h, L)) / (2 * dr);
        INFO("r " << r << ": E " << rec.e.g << " vs " << e << "; dE/dr " << rec.grad_t[1].x
                  << " vs " << de << ", tangential " << rec.grad_t[1].y);
        CHECK(rec.e.g == Approx(e).epsilon(0.02));
        CHECK(rec.grad_t[1].x == Approx(de).margin(0.05 * std::fabs(de) + 0.01 * e));
        CHECK(rec.grad_t[1].y == Approx(0.0).margin(0.05 * std::fabs(de) + 0.01 * e));
    }
    // Records on a 0.5 grid over [-2.5, 2.5]^2 (as a fill would leave them), then the
    // irradiance between them against the analytic value, with and without gradients.
    CacheParams with;
    CacheParams without;
    without.gradients = false;
    const Bounds3 box{{-3.f, -3.f, -1.f}, {3.f, 3.f, 2.f}};
    IrradianceCache cw(box, with), co(box, without);
    uint64_t seed = 11;
    for (float y = -2.5f; y <= 2.51f; y += 0.5f)
        for (float x = -2.5f; x <= 2.51f; x += 0.5f) {
            const IrradianceRecord rec =
                plane_light_record({x, y, 0.f}, up, in_disc, h, L, 2048, ++seed, 0.25f, 1.f);
            cw.insert(rec);
            co.insert(rec);
        }
    double se_with = 0.0, se_without = 0.0;
    int n = 0;
    CacheCounters st;
    const auto always = [](const IrradianceRecord&) { return true; };
    for (uint32_t i = 0; i < 4000; ++i) {
        const Vec3 p{4.f * rng::uniform(5, 1, i, 0) - 2.f, 4.f * rng::uniform(5, 1, i, 1) - 2.f,
                     0.f};
        RGB ew, eo;
        if (!cw.interpolate(p, up, ew, always, st) || !co.interpolate(p, up, eo, always, st))
            continue;
        const double e = disc_irradiance(length(p), a, h, L);
        se_with += (ew.g - e) * (ew.g - e);
        se_without += (eo.g - e) * (eo.g - e);
        ++n;
    }
    const double rmse_with = std::sqrt(se_with / n), rmse_without = std::sqrt(se_without / n);
    INFO("interpolated " << n << " of 4000; rmse with gradients " << rmse_with << ", without "
                         << rmse_without);
    CHECK(n > 3900);
    CHECK(rmse_with < 0.85 * rmse_without);
}

TEST_CASE("the visibility test keeps a lit room's records out of the dark room beyond a wall",
          "[cache][photon]") {
    // cache-leak.xml: no light can reach the right room, yet records on the left floor near
    // the parting wall reach across it. The records' rays see direct light only: a photon
    // estimate would bring its own leak (photons of the lit floor found across the wall's
    // foot), and the truth in the dark room would no longer be exactly zero.
    TestScene s = load_scene(test::source_path("scenes/cache-leak.xml"));
    s.set_resolution(128, 64);
    s.render.photon.global_photons = 50000;
    s.render.cache.secondary = CacheSecondary::Direct;
    const auto acc = make_intersector(s, s.accel);
    RenderOptions opt;
    opt.spp = 1;
    // The dark room's floor: the image half on the side where x > 0 projects, minus a margin
    // of 4 pixels at the parting wall.
    float fx, fy, cx, cy;
    REQUIRE(s.camera.project({1.f, 0.f, 0.f}, fx, fy));
    REQUIRE(s.camera.project({0.f, 1.f, 0.f}, cx, cy));
    // Mean and largest luminance on one side of the wall.
    auto side = [&](const Film& f, bool dark, double& mean, double& max) {
        double sum = 0.0;
        int n = 0;
        max = 0.0;
        for (int y = 0; y < f.height; ++y)
            for (int x = 0; x < f.width; ++x) {
                const bool right = fx > cx ? float(x) > cx + 4.f : float(x) < cx - 4.f;
                const bool left = fx > cx ? float(x) < cx - 4.f : float(x) > cx + 4.f;
                if (dark ? !right : !left) continue;
                const double v = f.pixels[std::size_t(y) * f.width + x].luminance();
                sum += v;
                max = std::max(max, v);
                ++n;
            }
        mean = sum / n;
    };
    const RenderResult on = render(s, s.render, *acc, opt);
    s.render.cache.visibility = false;
    const RenderResult off = render(s, s.render, *acc, opt);
    double on_mean, on_max, off_mean, off_max, lit_mean, lit_max;
    side(on.film, true, on_mean, on_max);
    side(off.film, true, off_mean, off_max);
    side(on.film, false, lit_mean, lit_max);
    INFO("dark room luminance, mean / max: visibility test on "
         << on_mean << " / " << on_max << ", off " << off_mean << " / " << off_max << "; lit room "
         << lit_mean << " / " << lit_max << "; rejections "
         << on.stats.cache.visibility_rejections);
    CHECK(on.stats.cache.visibility_rejections > 0);
    CHECK(on_max == 0.0);
    CHECK(off_max > 0.05 * lit_mean);
}

TEST_CASE("every secondary mode and the path renderer's cache agree with their references",
          "[cache][photon]") {
    TestScene s = load_scene(test::source_path("scenes/cornell-diffuse.xml"));
    // R_min is 1.5 pixel footprints and R_max 20 R_min: at a few dozen pixels across the
    // records would span the room.
    s.set_resolution(96, 96);
    const auto acc = make_intersector(s, s.accel);
    RenderOptions opt;
    opt.spp = 4;
    auto luminance_mean = [](const Film& f) {
        double sum = 0.0;
        for (const RGB& c : f.pixels) sum += std::min(c.luminance(), 2.f);
        return sum / double(f.pixels.size());
    };
    // Path tracing without and with the cache at the first diffuse vertex (records traced
    // onwards by path tracing): the same mean.
    s.render.integrator = "path";
    s.render.cache.samples = 256;
    const double path = luminance_mean(render(s, s.render, *acc, opt).film);
    s.render.indirect = IndirectMode::IrradianceCache;
    const RenderResult pc = render(s, s.render, *acc, opt);
    INFO("path " << path << ", path + cache " << luminance_mean(pc.film));
    CHECK(luminance_mean(pc.film) == Approx(path).epsilon(0.02));
    // One cache per bounce: three levels of indirect light, so a little darker than all of
    // them (each bounce returns at most 0.73 of the last), never brighter.
    s.render.cache.secondary = CacheSecondary::Cache;
    s.render.cache.levels = 3;
    s.render.cache.samples = 128;
    opt.threads = 1;
    const RenderResult levels = render(s, s.render, *acc, opt);
    const double lv = luminance_mean(levels.film);
    INFO("three cache levels " << lv << ", records " << levels.stats.cache_stored);
    CHECK(lv < path);
    CHECK(lv > 0.95 * path);
    opt.threads = 2;
    CHECK(compare_images(levels.film, render(s, s.render, *acc, opt).film).max_abs == 0.0);
    // Direct light only at the records' hits: one bounce, clearly darker.
    s.render.cache.samples = 256;
    s.render.cache.secondary = CacheSecondary::Direct;
    const double one = luminance_mean(render(s, s.render, *acc, opt).film);
    INFO("one bounce " << one);
    CHECK(one < 0.9 * lv);
    // The photon renderer: records from path tracing and from the photon map agree.
    s.render.integrator = "photon";
    s.render.photon.global_photons = 100000;
    s.render.photon.caustic_photons = 0;
    s.render.cache.secondary = CacheSecondary::Photon;
    const double photon = luminance_mean(render(s, s.render, *acc, opt).film);
    s.render.cache.secondary = CacheSecondary::Path;
    const double onwards = luminance_mean(render(s, s.render, *acc, opt).film);
    INFO("photon renderer: photon records " << photon << ", path-traced records " << onwards);
    CHECK(onwards == Approx(photon).epsilon(0.02));
    CHECK(onwards == Approx(path).epsilon(0.02));
}

TEST_CASE("ambient-occlusion records hold the unoccluded fraction", "[cache]") {
    // cache-leak.xml's open-topped rooms: from the middle of the left room's floor only the
    // open top is unoccluded, a cosine-weighted fraction F (Lambert's polygon formula); with
    // a hair's reach nothing is occluded.
    TestScene s = load_scene(test::source_path("scenes/cache-leak.xml"));
    s.set_resolution(128, 64);
    s.render.integrator = "path";
    s.render.cache.secondary = CacheSecondary::Occlusion;
    s.render.cache.samples = 1024;
    s.render.cache.r_max_factor = 1.f;  // records valid a pixel or two, not the whole room
    const auto acc = make_intersector(s, s.accel);
    RenderOptions opt;
    opt.spp = 4;
    s.render.cache.ao_distance = 1e-4f;
    const Film open = render(s, s.render, *acc, opt).film;
    s.render.cache.ao_distance = 0.f;  // unlimited
    const Film closed = render(s, s.render, *acc, opt).film;
    // White sky radiance 1 on a floor of rho 0.75; the direct light is the same in both, so
    // the difference is rho (1 - F).
    const Vec3 p{-1.f, 0.f, 0.f};
    float fx, fy;
    REQUIRE(s.camera.project(p, fx, fy));
    const std::size_t c = std::size_t(fy) * 128 + std::size_t(fx);
    const std::vector<Vec3> top = {{-2, 1, -1}, {0, 1, -1}, {0, 1, 1}, {-2, 1, 1}};
    const double F = polygon_irradiance(top, p, {0, 1, 0}, 1.0) / kPi;
    const RGB d = open.pixels[c] - closed.pixels[c];
    INFO("difference " << d.r << " " << d.g << " " << d.b << ", open top F = " << F);
    CHECK(d.r == Approx(0.75 * (1.0 - F)).epsilon(0.02));
    CHECK(d.g == Approx(0.75 * (1.0 - F)).epsilon(0.02));
    CHECK(d.b == Approx(0.75 * (1.0 - F)).epsilon(0.02));
}
