// Next event estimation's light choice (light_selection="power|uniform|bvh"): under the light
// BVH every triangle of an emissive mesh is a light of its own, the probabilities of all
// lights at a point sum to one, a pick's probability is what pick_pmf recomputes bit for bit,
// picks follow those probabilities (chi-square), no light that can reach a point is left
// out, and renders with each selection converge to the same image.
#include <catch2/catch.hpp>
#include <random>

#include "chi_square.h"
#include "engine/film/metrics.h"
#include "engine/scene/light_set.h"
#include "engine/scene/xml_loader.h"
#include "test_util.h"

using namespace foton;

namespace {

// Every kind of light: a point, a spot, a directional light, a rectangle, an emissive sphere,
// a two-sided quad, an environment and an emissive torus knot of 4,096 triangles facing every
// way, over a floor.
Scene many_kinds() {
    return parse_scene(R"(<scene><lights>
      <point intensity="3"><position x="0" y="5" z="0"/></point>
      <spot intensity="2" angle="40" inner_angle="20"><position x="1" y="4" z="0"/>
        <direction x="0" y="-1" z="0.2"/></spot>
      <directional intensity="0.5"><direction x="0.3" y="-1" z="0.2"/></directional>
      <area><radiance r="4" g="4" b="4"/><corner x="-1" y="4" z="-1"/><edge1 x="1.5" y="0" z="0"/>
        <edge2 x="0" y="0.3" z="1"/></area>
      <environment src="meshes/sky.hdr" intensity="0.3"/>
    </lights><objects>
      <quad name="floor"><corner x="-5" y="0" z="-5"/><edge1 x="0" y="0" z="10"/>
        <edge2 x="10" y="0" z="0"/><material type="lambert"/></quad>
      <sphere radius="0.5"><center x="2" y="3" z="1"/>
        <material type="lambert"><emission r="2" g="2" b="2"/></material></sphere>
      <quad name="panel"><corner x="1" y="2" z="-2"/><edge1 x="0" y="1" z="0.3"/>
        <edge2 x="-1" y="0.2" z="0"/><material type="lambert"><emission r="3" g="1" b="1" two_sided="true"/></material></quad>
      <triangle_mesh src="meshes/torus-knot.obj" smooth="false">
        <transform><scale s="1.2"/><translate x="-2" y="2.5" z="1"/></transform>
        <material type="lambert"><emission r="1" g="2" b="3"/></material></triangle_mesh>
    </objects><film width="8" height="8"/>
    <camera><eye x="0" y="1" z="-8"/><target x="0" y="1" z="0"/></camera></scene>)",
                       "lights.xml", test::source_path("scenes"));
}

// Each light next event estimation can pick: an emitter, and under bvh each of a mesh's
// triangles.
std::vector<std::pair<uint32_t, uint32_t>> units(const LightSet& ls) {
    std::vector<std::pair<uint32_t, uint32_t>> out;
    for (uint32_t i = 0; i < ls.size(); ++i) {
        const Emitter& e = ls.emitter(i);
        if (e.type == EmitterType::Mesh && ls.selection() == LightSelection::Bvh)
            for (uint32_t t = 0; t < e.tri_cdf.size(); ++t) out.push_back({i, t});
        else
            out.push_back({i, kWholeEmitter});
    }
    return out;
}

// Points above the floor and around the lights, with a normal (or none: a point in space).
struct Receiver {
    Vec3 p, n;
};
std::vector<Receiver> receivers(uint32_t seed, int count) {
    std::mt19937 g(seed);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    std::vector<Receiver> out;
    for (int k = 0; k < count; ++k) {
        const Vec3 p{4.f * u(g), 2.5f + 2.5f * u(g), 4.f * u(g)};
        Vec3 n{u(g), u(g), u(g)};
        n = k % 5 == 4 || length(n) < 0.1f ? Vec3{} : normalize(n);
        out.push_back({p, n});
    }
    return out;
}

}  // namespace

TEST_CASE("Light BVH: probabilities sum to one and a pick's equals pick_pmf",
          "[lights][bvh][fast]") {
    const Scene scene = many_kinds();
    for (const LightSelection sel :
         {LightSelection::Power, LightSelection::Uniform, LightSelection::Bvh}) {
        const LightSet ls(scene, sel);
        const auto all = units(ls);
        if (sel == LightSelection::Bvh) CHECK(all.size() > 4096);
        for (const Receiver& r : receivers(11, 24)) {
            double sum = 0.0;
            for (const auto& [light, tri] : all) sum += ls.pick_pmf(light, tri, r.p, r.n);
            INFO("selection " << int(sel) << " at " << r.p.x << " " << r.p.y << " " << r.p.z);
            // The BVH's descent can end at a node whose children both have importance 0 (the
            // parent's looser bound let it through): that mass picks no light, which costs a
            // sample, not bias. The rest sums to one.
            int failed = 0;
            const int picks = 4096;
            for (int k = 0; k < picks; ++k) {
                LightPick pick;
                const float u = (float(k) + 0.5f) / float(picks);
                if (!ls.pick(u, r.p, r.n, pick)) {
                    ++failed;
                    continue;
                }
                CHECK(pick.pmf > 0.f);
                CHECK(pick.pmf == ls.pick_pmf(pick.light, pick.tri, r.p, r.n));
            }
            if (sel != LightSelection::Bvh) CHECK(failed == 0);
            CHECK(sum + double(failed) / picks == Approx(1.0).margin(0.01));
            CHECK(sum <= 1.0 + 2e-4);
            CHECK(sum > 0.9);
        }
    }
}

TEST_CASE("Light BVH: picks follow their probabilities (chi-square)", "[lights][bvh]") {
    const Scene scene = many_kinds();
    const LightSet ls(scene, LightSelection::Bvh);
    const auto all = units(ls);
    std::mt19937 g(5);
    std::uniform_real_distribution<float> u01(0.f, 1.f);
    for (const Receiver& r : receivers(23, 4)) {
        std::vector<double> expected(all.size()), observed(all.size(), 0.0);
        const int n = test::scaled(200000);
        for (std::size_t k = 0; k < all.size(); ++k)
            expected[k] = n * double(ls.pick_pmf(all[k].first, all[k].second, r.p, r.n));
        std::vector<std::size_t> index_of(ls.size());
        for (std::size_t k = all.size(); k-- > 0;) index_of[all[k].first] = k;
        double failed = 0.0, expected_failed = n;
        for (const double e : expected) expected_failed -= e;
        for (int s = 0; s < n; ++s) {
            LightPick pick;
            if (!ls.pick(u01(g), r.p, r.n, pick)) {
                failed += 1.0;
                continue;
            }
            const std::size_t k = index_of[pick.light] + (pick.tri == kWholeEmitter ? 0 : pick.tri);
            REQUIRE(all[k].first == pick.light);
            observed[k] += 1.0;
        }
        // Pearson's statistic over bins pooled until each expects at least 5 picks; picks that
        // found no light are a bin of their own.
        double stat = 0.0, e_acc = 0.0, o_acc = 0.0;
        int bins = 0;
        if (expected_failed >= 5.0) {
            stat += (failed - expected_failed) * (failed - expected_failed) / expected_failed;
            ++bins;
        } else {
            e_acc = std::max(0.0, expected_failed);
            o_acc = failed;
        }
        for (std::size_t k = 0; k < all.size(); ++k) {
            if (expected[k] == 0.0) {
                CHECK(observed[k] == 0.0);  // a light of probability 0 is never picked
                continue;
            }
            e_acc += expected[k];
            o_acc += observed[k];
            if (e_acc >= 5.0) {
                stat += (o_acc - e_acc) * (o_acc - e_acc) / e_acc;
                ++bins;
                e_acc = o_acc = 0.0;
            }
        }
        if (e_acc > 0.0) stat += (o_acc - e_acc) * (o_acc - e_acc) / std::max(e_acc, 1.0);
        const double p = test::gamma_q(0.5 * (bins - 1), 0.5 * stat);
        INFO("chi2 " << stat << " bins " << bins << " p " << p);
        CHECK(bins > 50);
        CHECK(p > 1e-4);
    }
}

TEST_CASE("Light BVH: no light that reaches a point is left out", "[lights][bvh][fast]") {
    // A light left out of the choice would be missing from an estimate without MIS (final
    // gather, the irradiance cache's records): every light that sample_li can join to the
    // point, on the side its normal faces, must have a probability.
    const Scene scene = many_kinds();
    const LightSet ls(scene, LightSelection::Bvh);
    std::mt19937 g(9);
    std::uniform_real_distribution<float> u01(0.f, 1.f);
    int reached = 0, behind = 0;
    for (const Receiver& r : receivers(31, 12)) {
        for (const auto& [light, tri] : units(ls)) {
            bool reaches = false;
            for (int k = 0; k < 4 && !reaches; ++k) {
                LightSample s;
                if (!ls.sample_li(light, r.p, {u01(g), u01(g)}, u01(g), s, tri)) continue;
                reaches = s.pdf > 0.f && !s.Li.is_black() &&
                          (length(r.n) == 0.f || dot(s.wi, r.n) != 0.f);
            }
            const float pmf = ls.pick_pmf(light, tri, r.p, r.n);
            if (reaches) {
                ++reached;
                INFO("light " << light << " tri " << tri);
                CHECK(pmf > 0.f);
            } else if (pmf == 0.f) {
                ++behind;
            }
        }
    }
    CHECK(reached > 1000);
    CHECK(behind > 1000);  // the knot's triangles facing away are left out
}

TEST_CASE("Light selection: power, uniform and bvh render the same image", "[lights][render]") {
    // The choice changes the noise, not the estimate: each image's mean within 2 % of the
    // power selection's, and the per-pixel differences no larger than the noise. Also with
    // the scalar shading path (the kernel's lanes pick from the same surface point).
    Scene base = many_kinds();
    base.set_resolution(32, 32);
    auto render_with = [&](const char* selection, const char* shading) {
        Scene s = base;
        const RenderSettings defaults = render_settings(s);
        RenderSettings rs = defaults;
        rs.integrator = "path";
        rs.light_selection = std::string(selection) == "bvh"       ? LightSelection::Bvh
                             : std::string(selection) == "uniform" ? LightSelection::Uniform
                                                                   : LightSelection::Power;
        rs.simd_shading = std::string(shading) == "simd";
        const auto accel = make_intersector(s, AccelType::Bvh, 2);
        RenderOptions opt;
        opt.threads = 2;
        opt.spp = uint32_t(test::scaled(256));
        opt.seed = 4;
        return render(s, rs, *accel, opt).film;
    };
    const Film power = render_with("power", "simd");
    for (const auto& [selection, shading] : std::vector<std::pair<const char*, const char*>>{
             {"uniform", "simd"}, {"bvh", "simd"}, {"bvh", "scalar"}}) {
        const ImageError e = compare_images(render_with(selection, shading), power);
        const double mean_a = (e.mean_a.r + e.mean_a.g + e.mean_a.b) / 3.0;
        const double mean_b = (e.mean_b.r + e.mean_b.g + e.mean_b.b) / 3.0;
        INFO(selection << " " << shading << ": mean " << mean_a << " vs " << mean_b << " rmse "
                       << e.rmse);
        CHECK(mean_b > 0.05);
        CHECK(mean_a == Approx(mean_b).epsilon(0.02));
    }
}

TEST_CASE("Light BVH: the same image on 1 and 2 threads", "[lights][render]") {
    Scene s = many_kinds();
    s.set_resolution(24, 24);
    RenderSettings rs = render_settings(s);
    rs.integrator = "path";
    rs.light_selection = LightSelection::Bvh;
    auto run = [&](int threads) {
        const auto accel = make_intersector(s, AccelType::Bvh, threads);
        RenderOptions opt;
        opt.threads = threads;
        opt.spp = 8;
        opt.seed = 2;
        return render(s, rs, *accel, opt).film;
    };
    const ImageError e = compare_images(run(1), run(2));
    CHECK(e.max_abs == 0.0);
}

TEST_CASE("Light BVH: the SIMD descent equals its scalar twin bit for bit", "[lights][bvh][fast]") {
    // Through LightSet (lights at infinity, triangles of a mesh; power and uniform selection
    // too, which pick_lanes serves one at a time) and on a bare tree of 3,000 random lights of
    // every kind of bound: one-sided, two-sided, points, spots.
    const Scene scene = many_kinds();
    std::mt19937 g(17);
    std::uniform_real_distribution<float> u01(0.f, 1.f);
    const std::size_t n = 1024;  // a multiple of every SIMD width
    const std::vector<Receiver> rs = receivers(41, int(n));
    for (const LightSelection sel :
         {LightSelection::Bvh, LightSelection::Power, LightSelection::Uniform}) {
        const LightSet ls(scene, sel);
        LightPickLanes lanes(n);
        for (std::size_t i = 0; i < n; ++i) lanes.put(i, u01(g), rs[i].p, rs[i].n);
        const std::vector<float> u = lanes.u;
        ls.pick_lanes(lanes, n);
        std::size_t picked = 0;
        for (std::size_t i = 0; i < n; ++i) {
            LightPick one;
            const bool ok = ls.pick(u[i], rs[i].p, rs[i].n, one);
            INFO("selection " << int(sel) << " lane " << i);
            CHECK(ok == (lanes.out[i].pmf > 0.f));
            if (!ok) continue;
            ++picked;
            CHECK(lanes.out[i].light == one.light);
            CHECK(lanes.out[i].tri == one.tri);
            CHECK(lanes.out[i].pmf == one.pmf);
        }
        CHECK(picked > n * 9 / 10);
    }

    std::vector<LightBounds> bounds;
    for (int k = 0; k < 3000; ++k) {
        LightBounds b;
        const Vec3 c{20.f * u01(g) - 10.f, 5.f * u01(g), 20.f * u01(g) - 10.f};
        const float r = k % 7 == 0 ? 0.f : 0.3f * u01(g);
        b.box.extend(c - Vec3{r, r * 0.5f, r});
        b.box.extend(c + Vec3{r, r * 0.5f, r});
        b.axis = normalize(Vec3{u01(g) - 0.5f, -1.f, u01(g) - 0.5f});
        b.cos_o = k % 7 == 0 ? -1.f : (k % 11 == 0 ? 0.7f : 1.f);
        b.cos_e = k % 11 == 0 ? 1.f : 0.f;
        b.two_sided = k % 5 == 0;
        b.phi = 0.1f + 10.f * u01(g);
        bounds.push_back(b);
    }
    LightBvh bvh;
    bvh.build(bounds);
    std::vector<float> px(n), py(n), pz(n), nx(n), ny(n), nz(n), uu(n), pmf_a(n), pmf_b(n);
    std::vector<uint32_t> light_a(n), light_b(n);
    for (std::size_t i = 0; i < n; ++i) {
        px[i] = 24.f * u01(g) - 12.f;
        py[i] = 6.f * u01(g) - 0.5f;
        pz[i] = 24.f * u01(g) - 12.f;
        const Vec3 nn = i % 3 == 0 ? Vec3{} : normalize(Vec3{u01(g) - 0.5f, u01(g), u01(g) - 0.5f});
        nx[i] = nn.x;
        ny[i] = nn.y;
        nz[i] = nn.z;
        uu[i] = u01(g);
    }
    const kern::LightQueries qa{px.data(), py.data(), pz.data(),      nx.data(),   ny.data(),
                                nz.data(), uu.data(), light_a.data(), pmf_a.data()};
    kern::LightQueries qb = qa;
    qb.light = light_b.data();
    qb.pmf = pmf_b.data();
    kern::pick_lights(bvh.tree(), qa, n);
    kern::pick_lights_scalar(bvh.tree(), qb, n);
    std::size_t nonzero = 0;
    for (std::size_t i = 0; i < n; ++i) {
        INFO("query " << i);
        CHECK(pmf_a[i] == pmf_b[i]);
        CHECK(light_a[i] == light_b[i]);
        nonzero += pmf_a[i] > 0.f;
    }
    CHECK(nonzero > n / 2);
}
