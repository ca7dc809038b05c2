// Bidirectional path tracing, bidirectional photon mapping and vertex connection and merging
// (transport/bidir): every strategy alone converges to its share of the image, their MIS
// combination to the path tracer's image and to pbrt-v4's references, the white furnace,
// thread-count independence and the settings' errors.
#include <catch2/catch.hpp>
#include <cmath>

#include "engine/core/error.h"
#include "engine/film/image_io.h"
#include "engine/film/metrics.h"
#include "engine/scene/xml_loader.h"
#include "test_util.h"

using namespace foton;

namespace {

TestScene box(const char* file, int size, const std::string& type, uint32_t max_depth = 8) {
    TestScene s = load_scene(test::source_path(file));
    s.set_resolution(size, size);
    s.render.integrator = type;
    s.render.max_depth = max_depth;
    return s;
}

// Channel means over the pixels away from the light (its partly covered edge pixels are all
// or nothing at low sample counts).
RGB mean_away_from_light(const Film& img, const Film& ref) {
    const std::vector<uint8_t> mask =
        grow_exclusion(luminance_mask(ref, 2.f), ref.width, ref.height, 2);
    return compare_images(img, ref, &mask).mean_a;
}

void check_blocks(const Film& img, const Film& ref, int block, double tolerance) {
    const Film a = downsample(img, block), b = downsample(ref, block);
    double worst = 0;
    std::size_t where = 0;
    for (std::size_t i = 0; i < b.pixels.size(); ++i) {
        const double e = std::fabs(a.pixels[i].luminance() / b.pixels[i].luminance() - 1.0);
        if (e > worst) worst = e, where = i;
    }
    INFO("worst " << block << "x" << block << " block " << worst << " at (" << where % b.width
                  << ", " << where / b.width << ")");
    CHECK(worst < tolerance);
}

void check_means(const RGB& a, const RGB& b, double tolerance) {
    INFO("means " << a.r << " " << a.g << " " << a.b << " vs " << b.r << " " << b.g << " " << b.b);
    CHECK(a.r == Approx(b.r).epsilon(tolerance));
    CHECK(a.g == Approx(b.g).epsilon(tolerance));
    CHECK(a.b == Approx(b.b).epsilon(tolerance));
}

// Renders `path` (a path-traced scene) with path_spp samples, then with bdpt and vcm for
// `iterations`: channel means and block x block blocks within the tolerances.
void check_against_path(const TestScene& path, uint32_t path_spp, uint32_t iterations,
                        double mean_tolerance, int block, double block_tolerance) {
    const Film ref = render_test(path, path_spp, 0, 11).film;
    for (const char* type : {"bdpt", "vcm"}) {
        INFO(type);
        TestScene s = path;
        s.render.integrator = type;
        const Film img = render_test(s, iterations, 0, 12).film;
        const ImageError e = compare_images(img, ref);
        check_means(e.mean_a, e.mean_b, mean_tolerance);
        check_blocks(img, ref, block, block_tolerance);
    }
}

}  // namespace

TEST_CASE("bdpt, vcm and bpm agree with pbrt-v4 on the diffuse and caustics boxes",
          "[bidir][reference]") {
    const Film diffuse =
        downsample(read_exr(test::shared_path("refs/cornell_diffuse_path_512spp.exr")), 4);
    const Film caustics =
        downsample(read_exr(test::shared_path("refs/cornell_caustics_sppm_256it.exr")), 4);
    for (const char* type : {"bdpt", "vcm", "bpm"}) {
        INFO(type);
        // Merging alone (bpm) estimates every bounce's light by density: 4x the iterations
        // for the same noise.
        const bool bpm = std::string(type) == "bpm";
        const uint32_t spp = bpm ? 64 : 16;
        {
            const Film img = render_test(box("scenes/cornell-diffuse.xml", 128, type), spp).film;
            check_means(mean_away_from_light(img, diffuse), mean_away_from_light(diffuse, diffuse),
                        0.015);
            check_blocks(img, diffuse, bpm ? 32 : 16, 0.04);
        }
        {
            const Film img = render_test(box("scenes/cornell-caustics.xml", 128, type), spp).film;
            check_means(mean_away_from_light(img, caustics),
                        mean_away_from_light(caustics, caustics), 0.02);
            check_blocks(img, caustics, 32, 0.06);
        }
    }
}

TEST_CASE("every bdpt strategy alone converges to its share of the image", "[bidir]") {
    // Paths of 2 segments (direct light: camera - x1 - light) are found by (s, t) = (0, 3),
    // (1, 2) and (2, 1); paths of 3 segments by (0, 4), (1, 3), (2, 2) and (3, 1). Their
    // shares are the path tracer's max_depth 1 image less its max_depth 0 one (the light seen
    // directly), and its max_depth 2 image less its max_depth 1 one.
    auto path = [](uint32_t depth) {
        return render_test(box("scenes/cornell-diffuse.xml", 48, "path", depth), 256, 0, 5).film;
    };
    const Film p0 = path(0), p1 = path(1), p2 = path(2);
    const RGB m0 = mean_away_from_light(p0, p2), m1 = mean_away_from_light(p1, p2),
              m2 = mean_away_from_light(p2, p2);
    struct Strategy {
        int s, t;
    };
    for (uint32_t depth : {1u, 2u}) {
        const RGB share = depth == 1 ? m1 - m0 : m2 - m1;
        const std::vector<Strategy> list =
            depth == 1 ? std::vector<Strategy>{{0, 3}, {1, 2}, {2, 1}}
                       : std::vector<Strategy>{{0, 4}, {1, 3}, {2, 2}, {3, 1}};
        for (const Strategy st : list) {
            INFO("strategy (" << st.s << ", " << st.t << ")");
            TestScene s = box("scenes/cornell-diffuse.xml", 48, "bdpt", depth);
            s.render.bidir.only_s = st.s;
            s.render.bidir.only_t = st.t;
            const Film img = render_test(s, 128, 0, 7).film;
            // Measured at 256 spp: within 2.5 % for the 3-segment connection (2, 2), the
            // noisiest; within 1.3 % for the others.
            check_means(mean_away_from_light(img, p2), share, depth == 1 ? 0.03 : 0.06);
        }
    }
}

TEST_CASE("bdpt and vcm: white furnace, thread-count identity, settings", "[bidir][fast]") {
    // A sphere of albedo 0.6 emitting 0.5 on both sides, seen from inside: L = 0.5 / 0.4
    // (paths of 40 bounces miss 0.6^41 of it).
    auto furnace = [](const char* type) {
        return TestScene(parse_scene(
            std::string(R"(<scene><objects><sphere radius="1"><center x="0" y="0" z="0"/>
            <material type="lambert"><reflectance r="0.6" g="0.6" b="0.6"/>
            <emission r="0.5" g="0.5" b="0.5" two_sided="true"/></material></sphere></objects>
            <film width="16" height="16"/><renderer type=")") +
                type + R"(" max_depth="40"/>
            <camera fov="60"><eye x="0" y="0" z="0"/><target x="0" y="0" z="1"/></camera></scene>)",
            "furnace.xml", "."));
    };
    for (const char* type : {"bdpt", "vcm"}) {
        INFO(type);
        const Film img = render_test(furnace(type), 64).film;
        RGB sum{0.f};
        for (const RGB& p : img.pixels) sum += p;
        CHECK(sum.g / float(img.pixels.size()) == Approx(1.25f).epsilon(0.01));

        TestScene s = box("scenes/cornell-caustics.xml", 24, type);
        const Film one = render_test(s, 2, 1, 3).film, two = render_test(s, 2, 2, 3).film;
        CHECK(compare_images(one, two).max_abs == 0.0);
        CHECK(compare_images(one, render_test(s, 2, 2, 4).film).max_abs > 0.0);
        if (std::string(type) == "vcm") {
            // The kd-tree finds the same merges as the grid (in another order).
            s.render.bidir.merge_index = MergeIndex::KdTree;
            const Film kd = render_test(s, 2, 2, 3).film;
            CHECK(compare_images(kd, one).max_abs < 1e-4);
            CHECK(compare_images(kd, render_test(s, 2, 1, 3).film).max_abs == 0.0);
        }
    }

    auto settings_of = [](const std::string& renderer, const char* camera = "") {
        return render_settings(parse_scene(
            std::string(R"(<scene><objects><sphere radius="1"><center x="0" y="0" z="0"/>
            <material type="lambert"/></sphere></objects><film width="4" height="4"/>)") +
                renderer + "<camera " + camera +
                R"(><eye x="0" y="0" z="-5"/><target x="0" y="0" z="0"/></camera></scene>)",
            "b.xml", "."));
    };
    const RenderSettings one = settings_of(R"(<renderer type="bdpt" strategy="2,1"/>)");
    CHECK(one.bidir.only_s == 2);
    CHECK(one.bidir.only_t == 1);
    CHECK(settings_of(R"(<renderer type="bdpt" strategy="all"/>)").bidir.only_s == -1);
    CHECK_THROWS_WITH(settings_of(R"(<renderer type="bdpt" strategy="2"/>)"),
                      Catch::Contains("\"s,t\""));
    CHECK_THROWS_WITH(settings_of(R"(<renderer type="bdpt" strategy="2,0"/>)"),
                      Catch::Contains("t >= 1"));
    CHECK_THROWS_WITH(settings_of(R"(<renderer type="vcm" strategy="1,2"/>)"),
                      Catch::Contains("needs type=\"bdpt\""));
    CHECK(settings_of(R"(<renderer type="vcm" merge_index="kdtree"/>)").bidir.merge_index ==
          MergeIndex::KdTree);
    CHECK_THROWS_WITH(settings_of(R"(<renderer type="bdpt" merge_index="kdtree"/>)"),
                      Catch::Contains("needs type=\"bpm\" or \"vcm\""));
    CHECK_THROWS_WITH(settings_of(R"(<renderer type="vcm" rr_depth="3"/>)"),
                      Catch::Contains("rr_depth does not apply"));
    CHECK_THROWS_WITH(settings_of(R"(<renderer type="vcm" mis="max"/>)"),
                      Catch::Contains("balance or power"));
    // Light subpaths are joined to the eye: an orthographic camera cannot take them.
    const TestScene ortho = parse_scene(
        R"(<scene><lights><point><position x="0" y="2" z="0"/></point></lights><objects>
        <sphere radius="1"><center x="0" y="0" z="0"/><material type="lambert"/></sphere>
        </objects><film width="8" height="8"/><renderer type="bdpt"/>
        <camera type="orthographic"><eye x="0" y="0" z="5"/><target x="0" y="0" z="0"/>
        </camera></scene>)",
        "o.xml", ".");
    CHECK_THROWS_WITH(render_test(ortho, 1), Catch::Contains("needs a perspective camera"));
}

TEST_CASE("bdpt and vcm take every kind of light and BSDF the path tracer does", "[bidir]") {
    // Point, spot, directional, environment, an emitting sphere and an emitting quad (a mesh
    // emitter) at once, chosen by power, over Lambert, Phong and a rough conductor. No delta
    // surfaces: the path tracer cannot find a point light's caustics, bdpt can.
    const std::string xml = R"(<scene><lights>
        <point intensity="12"><color r="1" g="0.9" b="0.8"/><position x="0" y="4" z="-1"/></point>
        <spot intensity="40" angle="30" falloff="0.3"><color r="0.6" g="0.8" b="1"/>
          <position x="2" y="4" z="-1"/><target x="0" y="0" z="0"/></spot>
        <directional intensity="0.8"><color r="1" g="1" b="1"/><direction x="0.3" y="-1" z="0.4"/></directional>
        <environment intensity="0.3"><color r="0.8" g="0.9" b="1"/></environment></lights>
      <objects>
        <quad><corner x="-6" y="0" z="-6"/><edge1 x="0" y="0" z="12"/><edge2 x="12" y="0" z="0"/>
          <material type="lambert"><reflectance r="0.8" g="0.8" b="0.8"/></material></quad>
        <quad><corner x="-6" y="0" z="3"/><edge1 x="12" y="0" z="0"/><edge2 x="0" y="6" z="0"/>
          <material type="phong" c_diffuse="0.5" c_specular="0.3" exp="30"><base_color r="1" g="1" b="1"/>
          <specular_color r="1" g="1" b="1"/></material></quad>
        <sphere radius="1"><center x="-1.2" y="1" z="0"/>
          <material type="lambert"><reflectance r="0.7" g="0.3" b="0.2"/></material></sphere>
        <sphere radius="0.8"><center x="1.3" y="0.8" z="-0.5"/>
          <material type="conductor" preset="gold" roughness="0.2"/></sphere>
        <sphere radius="0.3"><center x="-2" y="3" z="-1"/><material type="lambert">
          <reflectance r="0" g="0" b="0"/><emission r="15" g="15" b="15"/></material></sphere>
        <quad><corner x="1" y="3.5" z="0"/><edge1 x="0.6" y="0" z="0"/><edge2 x="0" y="0" z="0.6"/>
          <material type="lambert"><reflectance r="0" g="0" b="0"/><emission r="10" g="8" b="6"/></material></quad>
      </objects><film width="32" height="24"/><renderer type="path" max_depth="5"/>
      <camera fov="40"><eye x="0" y="2.6" z="-8"/><target x="0" y="0.9" z="0"/></camera></scene>)";
    TestScene path = parse_scene(xml, "lights.xml", ".");
    // The path tracer is the noisier one here (the small emitting sphere reached by BSDF
    // samples): two 16,384 spp renders of an 8 x 8 block differ by RMSE 0.057 per pixel.
    // Measured: means within 0.6 %, 8 x 8 blocks within 4 % (the reference's noise).
    check_against_path(path, 4096, 256, 0.01, 8, 0.06);
}

TEST_CASE("bdpt and vcm through the thin lens: the materials scene as the path tracer sees it",
          "[bidir]") {
    // Every BSDF of foton (Lambert, Oren-Nayar, rough and smooth conductors, glass,
    // anisotropic metal, plastic, a Lambert + mirror mix) seen through a thin lens: light
    // subpaths are joined to a point sampled on the lens.
    TestScene path = load_scene(test::source_path("scenes/materials.xml"));
    path.set_resolution(48, 32);
    path.render.integrator = "path";
    REQUIRE(path.camera.lens_radius > 0.f);
    // Measured at 96 x 64, 256 iterations: means within 0.4 %.
    check_against_path(path, 1024, 128, 0.015, 16, 0.05);
}
