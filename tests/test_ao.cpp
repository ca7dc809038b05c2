// The ambient-occlusion integrator (transport/ao, the example of adding an integrator by its
// folder and one table row): the open fraction under a square ceiling against the analytic
// view factor, the distance limit, and its settings' checks.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "engine/accel/intersector.h"
#include "engine/core/error.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/render.h"
#include "test_util.h"

using namespace foton;

namespace {

// A floor, and a square ceiling of half-size a at height 1 centred over the origin; a narrow
// camera between them looks straight down at the origin.
Scene ceiling(float a, const std::string& renderer) {
    const std::string lo = std::to_string(-a), size = std::to_string(2.f * a);
    return parse_scene(
        R"(<scene><objects>
      <quad name="floor"><corner x="-50" y="0" z="-50"/><edge1 x="100" y="0" z="0"/>
        <edge2 x="0" y="0" z="100"/><material type="lambert"/></quad>
      <quad name="ceiling"><corner x=")" +
            lo + R"(" y="1" z=")" + lo + R"("/><edge1 x=")" + size +
            R"(" y="0" z="0"/><edge2 x="0" y="0" z=")" + size +
            R"("/><material type="lambert"/></quad>
      </objects><film width="4" height="4"/>
      <renderer )" +
            renderer + R"(/>
      <camera fov="0.5"><eye x="0" y="0.5" z="0"/><target x="0" y="0" z="0"/>
        <up x="0" y="0" z="1"/></camera></scene>)",
        "ao.xml", ".");
}
TestScene ceiling_scene(float a, const std::string& ao_settings) {
    return TestScene(ceiling(a, R"(type="ao" )" + ao_settings));
}

// View factor from a differential area to a parallel rectangle a x b at height 1 with one
// corner straight above it (the standard form-factor table).
double corner_factor(double a, double b) {
    const double sa = std::sqrt(1.0 + a * a), sb = std::sqrt(1.0 + b * b);
    return (a / sa * std::atan(b / sa) + b / sb * std::atan(a / sb)) / (2.0 * std::acos(-1.0));
}

double mean(const Film& f) {
    double s = 0.0;
    for (const RGB& c : f.pixels) s += c.r;
    return s / double(f.pixels.size());
}

}  // namespace

TEST_CASE("ambient occlusion under a square ceiling is one minus its view factor", "[ao][fast]") {
    for (float a : {0.5f, 1.f, 3.f}) {
        INFO("half-size " << a);
        const TestScene s = ceiling_scene(a, R"(ao_samples="4096")");
        const auto acc = make_intersector(s, AccelType::Bvh);
        RenderOptions opt;
        opt.spp = 1;
        const Film f = render(s, s.render, *acc, opt).film;
        const double expect = 1.0 - 4.0 * corner_factor(a, a);
        // 16 pixels x 4096 cosine-weighted rays: the binomial standard error is under 0.002.
        CHECK(mean(f) == Approx(expect).margin(0.01));
        // Below the ceiling's height nothing closes the hemisphere.
        const TestScene near = ceiling_scene(a, R"(ao_samples="64" ao_distance="0.9")");
        const Film open = render(near, near.render, *acc, opt).film;
        for (const RGB& c : open.pixels) CHECK(c.r == 1.f);
    }
}

TEST_CASE("ambient occlusion's settings are checked at their file and line", "[ao][fast]") {
    CHECK_THROWS_WITH(ceiling_scene(1.f, R"(ao_samples="0")"), Catch::Contains("ao_samples"));
    CHECK_THROWS_WITH(ceiling_scene(1.f, R"(ao_distance="-1")"), Catch::Contains("ao_distance"));
    // Another integrator does not take them: a warning, ignored; a key nobody knows is an error.
    const RenderSettings path = render_settings(ceiling(1.f, R"(type="path" ao_samples="4")"));
    REQUIRE(path.warnings.size() == 1);
    CHECK_THAT(path.warnings[0], Catch::Contains("'ao_samples' belongs to type=\"ao\"") &&
                                     Catch::Contains("ignored by type=\"path\""));
    CHECK_THROWS_WITH(render_settings(ceiling(1.f, R"(type="path" ao_sample="4")")),
                      Catch::Contains("unknown setting 'ao_sample'"));
}
