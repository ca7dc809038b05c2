// The SIMD shading kernel of Lambertian vertices (kernels/diffuse_shade.h): bit for bit equal
// to its scalar twin on random vertex sets with every edge the engine produces (surfaces made
// from flat and smooth triangles and spheres, lights behind the surface, leaning shading
// normals, lights at infinity, the disc's centre, roulette), the
// twin's directions equal to the engine's own Lambert sampling, and renders with the kernel
// equal to renders without it up to float rounding.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <random>

#include "engine/core/aligned.h"
#include "engine/core/warp.h"
#include "engine/film/metrics.h"
#include "engine/scene/bsdf.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/common/camera_integrator.h"
#include "kernels/diffuse_shade.h"
#include "kernels/lane_compress.h"
#include "kernels/specular_shade.h"
#include "shade_vertices.h"
#include "test_util.h"

using namespace foton;
using namespace foton::kern;
using test::bits;
using test::random_unit;
using test::random_vertices;
using test::Table;

namespace {

Film render_path(const std::string& scene_file, const RendererOverrides& settings) {
    Scene scene = load_scene(test::source_path("scenes/" + scene_file), settings);
    scene.set_resolution(48, 48);
    const RenderSettings rs = render_settings(scene);
    const auto accel = make_intersector(scene, AccelType::Bvh, 2);
    RenderOptions opt;
    opt.threads = 2;
    opt.spp = 16;
    opt.seed = 3;
    return render(scene, rs, *accel, opt).film;
}

// The lanes as specular vertices: mirrors (no Fresnel term, a conductor's, a dielectric's)
// and dielectrics of several indices, hit from either side; `bsdfs` gets each lane's BSDF as
// the engine builds it.
void make_specular(Table& t, std::size_t n, uint32_t seed, std::vector<Bsdf>& bsdfs) {
    std::mt19937 g(seed);
    std::uniform_real_distribution<float> u01(0.f, 1.f);
    bsdfs.assign(n, Bsdf{});
    for (std::size_t i = 0; i < n; ++i) {
        const RGB color{0.5f + 0.5f * u01(g), 0.9f, 0.3f + 0.7f * u01(g)};
        Lobe lobe;
        if (i % 2 == 0) {
            Fresnel f;
            if (i % 6 == 2) {
                f.kind = FresnelKind::Conductor;
                f.eta = RGB{0.2f + u01(g), 0.9f, 1.1f};
                f.k = RGB{3.f + u01(g), 2.5f, 2.f};
            } else if (i % 6 == 4) {
                f.kind = FresnelKind::Dielectric;
                f.ior = 1.3f + u01(g);
            }
            lobe = Lobe::mirror(color, f);
        } else {
            lobe = Lobe::dielectric(1.2f + u01(g), color, RGB{u01(g), 1.f, 0.8f});
        }
        bsdfs[i].add(lobe);
        t.at(kDvSpecKind, i) = lobe.type == LobeType::Mirror ? 1.f : 2.f;
        t.set3(kDvSpecR, i, {lobe.color.r, lobe.color.g, lobe.color.b});
        t.set3(kDvTransR, i, {lobe.transmit.r, lobe.transmit.g, lobe.transmit.b});
        t.at(kDvFresnel, i) = lobe.fresnel.kind == FresnelKind::Conductor    ? 1.f
                              : lobe.fresnel.kind == FresnelKind::Dielectric ? 2.f
                                                                             : 0.f;
        t.at(kDvIor, i) = lobe.fresnel.ior;
        t.set3(kDvEtaR, i, {lobe.fresnel.eta.r, lobe.fresnel.eta.g, lobe.fresnel.eta.b});
        t.set3(kDvKR, i, {lobe.fresnel.k.r, lobe.fresnel.k.g, lobe.fresnel.k.b});
        t.at(kDvLobeWeight, i) = bsdfs[i].weight(0);
        t.at(kDvUChoice, i) = u01(g);
        t.at(kDvSurface, i) = 0.f;  // the random surface columns as they are
        t.at(kDvFront, i) = i % 4 == 1 ? 0.f : 1.f;
    }
}

}  // namespace

TEST_CASE("Diffuse shading kernel: SIMD equals its scalar twin bit for bit",
          "[kernel][shade][fast]") {
    const std::size_t n = 4099;  // not a multiple of any SIMD width
    for (const DiffuseMis mis : {DiffuseMis::Balance, DiffuseMis::Power, DiffuseMis::Maximum,
                                 DiffuseMis::Mean, DiffuseMis::None}) {
        for (const bool roulette : {false, true}) {
            Table a = random_vertices(n, 7u + uint32_t(mis)), b = a;
            const DiffuseRules rules{mis, roulette};
            shade_diffuse(a.view(), n, rules);
            shade_diffuse_scalar(b.view(), n, rules);
            const test::TwinComparison r = test::compare_twin(a, b, n);
            INFO("first lane that differs: " << r.first_bad_lane);
            CHECK(r.validity_mismatches == 0);
            CHECK(r.bit_mismatches == 0);
            // The sets exercise both outcomes of both tests.
            CHECK(r.shadows > n / 5);
            CHECK(r.shadows < n);
            CHECK(r.nexts > n / 3);
            CHECK(r.nexts < n);
        }
    }
}

TEST_CASE("Diffuse shading kernel: the twin samples as the engine's Lambert and Oren-Nayar lobes",
          "[kernel][shade][fast]") {
    const std::size_t n = 2000;
    Table t = random_vertices(n, 99);
    shade_diffuse_scalar(t.view(), n, DiffuseRules{DiffuseMis::Power, false});
    std::size_t compared = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (t.at(kDvNextValid, i) == 0.f) continue;
        const Vec3 ns{t.at(kDvNsx, i), t.at(kDvNsy, i), t.at(kDvNsz, i)};
        const Vec3 wo{t.at(kDvWox, i), t.at(kDvWoy, i), t.at(kDvWoz, i)};
        const RGB rho{t.at(kDvRhoR, i), t.at(kDvRhoG, i), t.at(kDvRhoB, i)};
        const warp::Frame frame(ns);
        BsdfSample s;
        Lobe lobe = Lobe::lambert(rho);
        if (t.at(kDvOnB, i) != 0.f) {
            lobe.type = LobeType::OrenNayar;
            lobe.on_a = t.at(kDvOnA, i);
            lobe.on_b = t.at(kDvOnB, i);
        }
        REQUIRE(lobe_sample(lobe, frame.to_local(wo), 0.5f, {t.at(kDvU0, i), t.at(kDvU1, i)},
                            BsdfContext{}, s));
        const Vec3 wi = frame.to_world(s.wi);
        const Vec3 k{t.at(kDvNdx, i), t.at(kDvNdy, i), t.at(kDvNdz, i)};
        // The two sines and cosines differ by an ulp; near the horizon z = sqrt(1 - x^2 - y^2)
        // magnifies that by 1 / z, so the tolerances are absolute.
        CHECK(length(wi - k) < 1e-4f);
        CHECK(t.at(kDvNpdf, i) == Approx(s.pdf).epsilon(1e-5).margin(3e-5));
        const RGB beta{t.at(kDvBetaR, i), t.at(kDvBetaG, i), t.at(kDvBetaB, i)};
        const RGB expect = beta * s.f * (std::fabs(s.wi.z) / s.pdf);
        CHECK(t.at(kDvNbetaR, i) == Approx(expect.r).epsilon(1e-5));
        CHECK(t.at(kDvNbetaB, i) == Approx(expect.b).epsilon(1e-5));
        ++compared;
    }
    CHECK(compared > n / 3);
}

TEST_CASE("Diffuse shading kernel: path renders equal the scalar shading's up to rounding",
          "[render][shade]") {
    // The Lambertian box, and the mirror + glass box, where kernel and scalar vertices meet on
    // one path; each MIS heuristic, BSDF sampling alone, and roulette from the first vertex.
    const std::vector<std::pair<const char*, RendererOverrides>> cases = {
        {"cornell-diffuse.xml", {{"mis", "power"}}},
        {"cornell-diffuse.xml", {{"mis", "balance"}, {"rr_depth", "1"}}},
        {"cornell-diffuse.xml", {{"mis", "max"}}},
        {"cornell-diffuse.xml", {{"mis", "mean"}}},
        {"cornell-diffuse.xml", {{"mis", "none"}}},
        {"cornell-diffuse.xml", {{"nee", "false"}}},
        {"smallvcm-box.xml", {{"mis", "power"}}},
        {"cornell-caustics.xml", {{"rr_depth", "1"}}},
        {"cornell-box.xml", {{"mis", "power"}}},
        {"materials.xml", {{"mis", "balance"}}},
        // GGX lobes (isotropic and anisotropic, conductor and plastic) in the glossy lanes.
        {"ggx-spheres.xml", {{"mis", "power"}}},
        // Triangles of emissive meshes sampled in the kernel: chosen by area within the mesh,
        // and each its own light under the light BVH.
        {"textured-meshes.xml", {{"mis", "power"}}},
        {"textured-meshes.xml", {{"light_selection", "bvh"}}},
        {"cornell-diffuse.xml", {{"light_selection", "bvh"}}},
        // The samplers' tables: Halton, Sobol', Z-Sobol'.
        {"cornell-diffuse.xml", {{"sampler", "halton"}}},
        {"cornell-diffuse.xml", {{"sampler", "sobol"}}},
        {"cornell-diffuse.xml", {{"sampler", "zsobol"}}},
        // Spheres sampled in the kernel by the cone they subtend.
        {"mis-plates.xml", {{"mis", "power"}}},
    };
    for (const auto& [scene_name, settings] : cases) {
        RendererOverrides simd = settings, scalar = settings;
        simd.push_back({"type", "path"});
        scalar.push_back({"type", "path"});
        scalar.push_back({"shading", "scalar"});
        const ImageError e =
            compare_images(render_path(scene_name, simd), render_path(scene_name, scalar));
        const double mean = (e.mean_b.r + e.mean_b.g + e.mean_b.b) / 3.0;
        INFO(scene_name << " rmse " << e.rmse << " mean " << mean);
        CHECK(mean > 0.01);
        CHECK(e.rmse < 2e-3 * mean);
    }
}

TEST_CASE("Specular shading kernel: SIMD equals its scalar twin, and the twin the engine's lobes",
          "[kernel][shade][fast]") {
    const std::size_t n = 3001;
    for (const bool roulette : {false, true}) {
        Table a = random_vertices(n, 21), b = a;
        std::vector<Bsdf> bsdfs;
        make_specular(a, n, 5, bsdfs);
        make_specular(b, n, 5, bsdfs);
        shade_specular(a.view(), n, roulette);
        shade_specular_scalar(b.view(), n, roulette);
        std::size_t nexts = 0, refracted = 0, mismatches = 0, engine_mismatches = 0;
        for (std::size_t i = 0; i < n; ++i) {
            REQUIRE(a.at(kDvNextValid, i) == b.at(kDvNextValid, i));
            REQUIRE(a.at(kDvShadowValid, i) == 0.f);
            if (a.at(kDvNextValid, i) == 0.f) continue;
            ++nexts;
            refracted += a.at(kDvNtransmit, i) != 0.f;
            for (uint32_t c = kDvNox; c <= kDvNtransmit; ++c)
                if (bits(a.at(c, i)) != bits(b.at(c, i))) ++mismatches;
            if (roulette) continue;
            // The engine's sample of the same lobe: the same direction and weight, exactly.
            const Vec3 ns{b.at(kDvNsx, i), b.at(kDvNsy, i), b.at(kDvNsz, i)};
            const Vec3 wo{b.at(kDvWox, i), b.at(kDvWoy, i), b.at(kDvWoz, i)};
            const warp::Frame frame(ns);
            BsdfSample s;
            const BsdfContext ctx{b.at(kDvFront, i) != 0.f, Transport::Radiance};
            REQUIRE(bsdfs[i].sample(frame.to_local(wo), b.at(kDvUChoice, i), {0.5f, 0.5f}, ctx, s));
            const Vec3 wi = frame.to_world(s.wi);
            const RGB beta{b.at(kDvBetaR, i), b.at(kDvBetaG, i), b.at(kDvBetaB, i)};
            const RGB w = beta * (s.f * (std::fabs(s.wi.z) / s.pdf));
            engine_mismatches += !(wi == Vec3{b.at(kDvNdx, i), b.at(kDvNdy, i), b.at(kDvNdz, i)});
            engine_mismatches += w.r != b.at(kDvNbetaR, i) || w.b != b.at(kDvNbetaB, i);
            engine_mismatches += s.pdf != b.at(kDvNpdf, i);
            engine_mismatches += b.at(kDvNetaScale, i) != b.at(kDvEtaScale, i) * (s.eta * s.eta);
        }
        CHECK(mismatches == 0);
        CHECK(engine_mismatches == 0);
        CHECK(nexts > n / 4);
        CHECK(refracted > n / 20);
        CHECK(refracted < nexts);
    }
}

TEST_CASE("Camera rays: the Sobol' and Z-Sobol' pixel tables equal pixel_sample",
          "[sampler][kernel][fast]") {
    Scene scene = load_scene(test::source_path("scenes/cornell-diffuse.xml"));
    scene.set_resolution(37, 29);
    std::mt19937 g(4);
    std::vector<SampleJob> jobs;
    for (uint32_t k = 0; k < 203; ++k) {
        SampleJob j;
        j.x = g() % 37;
        j.y = g() % 29;
        j.pat_n = 1u + g() % 33;
        j.pat_i = g() % j.pat_n;
        j.pat_round = g() % 3;
        j.id = k;
        jobs.push_back(j);
    }
    for (const SamplerKind kind : {SamplerKind::Sobol, SamplerKind::ZSobol}) {
        std::vector<float> table;
        REQUIRE(pixel_sample_table(scene, kind, jobs, 17, table));
        const std::size_t stride = table.size() / 2;
        std::size_t differ = 0;
        for (std::size_t s = 0; s < jobs.size(); ++s) {
            const Point2 p = pixel_sample(scene, kind, jobs[s], 17);
            differ += (p.x != table[s]) + (p.y != table[stride + s]);
        }
        CHECK(differ == 0);
    }
    std::vector<float> table;
    CHECK_FALSE(pixel_sample_table(scene, SamplerKind::Jittered, jobs, 17, table));
}

TEST_CASE("Lane compression: AVX-512 compress stores equal the scalar twin",
          "[kernel][shade][fast]") {
    std::mt19937 g(11);
    std::uniform_real_distribution<float> u01(0.f, 1.f);
    for (const std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(15), std::size_t(16),
                                std::size_t(17), std::size_t(64), std::size_t(63)}) {
        for (const float density : {0.f, 0.3f, 1.f}) {
            std::vector<float> valid(n);
            std::vector<uint32_t> a(n), b(n);
            for (std::size_t k = 0; k < n; ++k) {
                valid[k] = u01(g) < density ? (k % 5 == 0 ? std::nanf("") : 1.f) : 0.f;
                a[k] = uint32_t(g());
                b[k] = uint32_t(k);
            }
            const uint32_t* src[2] = {a.data(), b.data()};
            std::vector<uint32_t> x0(n + 1, 7u), x1(n + 1, 7u), y0(n + 1, 7u), y1(n + 1, 7u);
            uint32_t* const simd_dst[2] = {x0.data(), x1.data()};
            uint32_t* const twin_dst[2] = {y0.data(), y1.data()};
            const std::size_t m = compress_lanes(valid.data(), n, src, simd_dst, 2);
            const std::size_t m2 = compress_lanes_scalar(valid.data(), n, src, twin_dst, 2);
            std::size_t expect = 0;
            for (const float v : valid) expect += v != 0.f;
            CHECK(m == expect);
            CHECK(m2 == expect);
            CHECK(x0 == y0);  // also: nothing past the packed lanes is written
            CHECK(x1 == y1);
        }
    }
}
