// Values an accepted scene may hold (issue 34, defects 6-8): emission beyond what float sums
// can hold, numbers beyond float's range in pbrt files, geometry beyond +-1e18, and a
// checkerboard scaled by 1e30 were accepted and gave NaN, black or undefined behaviour; each
// is now refused at its file and line, or (the checkerboard) defined.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <string>

#include "engine/core/error.h"
#include "engine/scene/environment.h"
#include "engine/scene/pbrt_loader.h"
#include "engine/scene/texture.h"
#include "engine/scene/xml_loader.h"
#include "test_util.h"

using namespace foton;

namespace {

const char* kXmlFilmCamera = R"(<scene>
  <film width="8" height="8" size="0.01"/>
  <camera type="perspective" d="1"><eye x="0" y="0" z="5"/><target x="0" y="0" z="0"/></camera>
)";

// The error of an XML scene whose lights are `lights` and whose objects are `objects`.
std::string xml_error(const std::string& lights, const std::string& objects = "") {
    const std::string xml =
        std::string(kXmlFilmCamera) + "<lights>" + lights + "</lights>\n<objects>" +
        (objects.empty()
             ? R"(<sphere radius="1"><center x="0" y="0" z="0"/><material type="matte"/></sphere>)"
             : objects) +
        "</objects>\n</scene>";
    try {
        parse_scene(xml, "s.xml", ".");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

std::string pbrt_error(const std::string& world) {
    const std::string text = "Camera \"perspective\"\nWorldBegin\n" + world +
                             "\nShape \"trianglemesh\" \"point3 P\" [-1 -1 0  1 -1 0  1 1 0] "
                             "\"integer indices\" [0 1 2]\n";
    try {
        parse_pbrt_scene(text, "t.pbrt", ".");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("XML: emission beyond what float sums hold is refused at its line",
          "[xml][security][fast]") {
    CHECK_THAT(xml_error(R"(<point intensity="1e38"><position x="0" y="3" z="0"/></point>)"),
               Catch::Contains("s.xml:4") && Catch::Contains("above foton's limit"));
    CHECK_THAT(xml_error("", R"(<sphere radius="1"><center x="0" y="0" z="0"/>
        <material type="matte"><emission r="3e38" g="1" b="1"/></material></sphere>)"),
               Catch::Contains("above foton's limit"));
    // Colour x intensity: each finite, the product not.
    CHECK_THAT(xml_error(R"(<directional intensity="1e20"><color r="1e20" g="1" b="1"/>
        <direction x="0" y="-1" z="0"/></directional>)"),
               Catch::Contains("NaN or infinite"));
    CHECK(xml_error(R"(<point intensity="1e6"><position x="0" y="3" z="0"/></point>)").empty());
}

TEST_CASE("XML: geometry beyond +-1e18 is refused", "[xml][security][fast]") {
    CHECK_THAT(
        xml_error(
            "",
            R"(<sphere radius="1"><center x="3e38" y="0" z="0"/><material type="matte"/></sphere>)"),
        Catch::Contains("s.xml") && Catch::Contains("coordinates must be finite"));
}

TEST_CASE("pbrt-v4: numbers beyond float's range and emission beyond the limit are refused",
          "[pbrt][security][fast]") {
    CHECK_THAT(pbrt_error("Translate 1e39 0 0"),
               Catch::Contains("t.pbrt:3") && Catch::Contains("beyond the range of a float"));
    CHECK_THAT(pbrt_error("Translate 0 0 1e300"), Catch::Contains("beyond the range of a float"));
    CHECK_THAT(pbrt_error("Shape \"sphere\" \"float radius\" [1e39]"),
               Catch::Contains("t.pbrt:3") && Catch::Contains("beyond the range of a float"));
    CHECK_THAT(pbrt_error("LightSource \"point\" \"rgb I\" [1e39 1 1]"),
               Catch::Contains("beyond the range of a float"));
    CHECK_THAT(pbrt_error("LightSource \"point\" \"rgb I\" [3e38 1 1]"),
               Catch::Contains("t.pbrt:3") && Catch::Contains("above foton's limit"));
    CHECK_THAT(pbrt_error("AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [3e38 3e38 3e38]\n"
                          "Shape \"sphere\"\nAttributeEnd"),
               Catch::Contains("t.pbrt:4") && Catch::Contains("above foton's limit"));
    // Two translations of 3e38 each: every number in range, the sum not.
    CHECK_THAT(pbrt_error("Translate 3e38 0 0\nTranslate 3e38 0 0\nShape \"sphere\""),
               Catch::Contains("coordinates must be finite"));
    CHECK(pbrt_error("LightSource \"point\" \"rgb I\" [100 100 100]").empty());
}

TEST_CASE("Environment maps: a texel times the scale beyond the limit is refused",
          "[environment][security][fast]") {
    TextureImage map;
    map.path = "sky.hdr";
    map.width = 2;
    map.height = 1;
    // What an HDR texel with exponent 255 decodes to.
    map.texels = {RGB{1.f}, RGB{std::ldexp(1.f, 127)}};
    CHECK_THROWS_WITH(Environment::image(map, EnvMapping::LatLong, RGB{1.f}, {0, 1, 0}, {0, 0, 1}),
                      Catch::Contains("sky.hdr") && Catch::Contains("above foton's limit"));
    map.texels[1] = RGB{NAN};
    CHECK_THROWS_WITH(Environment::image(map, EnvMapping::LatLong, RGB{1.f}, {0, 1, 0}, {0, 0, 1}),
                      Catch::Contains("NaN or infinite"));
    map.texels[1] = RGB{2.f};
    CHECK_NOTHROW(Environment::image(map, EnvMapping::LatLong, RGB{1.f}, {0, 1, 0}, {0, 0, 1}));
}

TEST_CASE("Checkerboards: the pattern is defined for any scale (1e30 once was UB)",
          "[texture][security][fast]") {
    CHECK(checker_even({0.5f, 0.5f}));
    CHECK_FALSE(checker_even({1.5f, 0.5f}));
    CHECK_FALSE(checker_even({-0.5f, 0.5f}));
    CHECK(checker_even({-0.5f, -0.5f}));
    // 2.2e29 is an even integer; 3.5 floors to an odd one.
    CHECK(checker_even({2.2e29f, 0.5f}));
    CHECK_FALSE(checker_even({2.2e29f, 3.5f}));
    Texture t;
    t.kind = TextureKind::Checkerboard;
    t.value = RGB{1.f};
    t.other = RGB{0.f};
    t.uv.su = 1e30f;
    t.uv.sv = 1e30f;
    const RGB v = t.eval({}, Point2{0.3f, 0.7f});
    CHECK(std::isfinite(v.r));
}
