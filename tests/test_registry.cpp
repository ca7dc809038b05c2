// The integrator table (transport/registry/integrators.h) is the one list of integrators:
// names and aliases resolve, the capability wording of error messages comes from it, and the
// scene format's documentation and the command line's help cover every row.
#include <catch2/catch.hpp>

#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/integrators.h"
#include "test_util.h"

using namespace foton;

TEST_CASE("every row of the integrator table resolves, is documented and is in the help",
          "[registry][fast]") {
    std::ifstream in(test::source_path("scenes/README.md"));
    REQUIRE(in);
    std::stringstream doc;
    doc << in.rdbuf();
    const std::string help = integrator_help();
    std::set<std::string> seen;
    for (const IntegratorInfo& i : integrators()) {
        INFO(i.name);
        CHECK(seen.insert(i.name).second);
        CHECK(find_integrator(i.name) == &i);
        for (const char* a : i.aliases) {
            CHECK(seen.insert(a).second);
            CHECK(find_integrator(a) == &i);
        }
        CHECK(i.render != nullptr);
        CHECK(std::string(i.summary).size() > 0);
        CHECK(doc.str().find(std::string("`") + i.name + "`") != std::string::npos);
        CHECK(help.find(std::string("\n  ") + i.name) != std::string::npos);
    }
    CHECK(find_integrator("no-such") == nullptr);
}

TEST_CASE("capability wording names the rows that have it", "[registry][fast]") {
    CHECK(integrators_with(kCapStrategyDebug) == "type=\"bdpt\"");
    CHECK(integrators_with(kCapMerging) == "type=\"bpm\" or \"vcm\"");
    CHECK(integrators_with(kCapBidirectional) == "type=\"bdpt\", \"bpm\" or \"vcm\"");
    // Adaptive sampling needs a camera integrator: the table says which.
    const std::string camera = integrators_with(kCapCamera);
    for (const IntegratorInfo& i : integrators()) {
        const bool named = camera.find(std::string("\"") + i.name + "\"") != std::string::npos;
        CHECK(named == i.has(kCapCamera));
    }
}

TEST_CASE("what an integrator cannot do is refused at the setting's file and line",
          "[registry][fast]") {
    struct Case {
        const char* renderer;
        const char* message;
        bool warning;  // a setting for another integrator: warned about and ignored
    };
    for (const Case& c :
         {Case{R"(type="light" adaptive="true")", "adaptive sampling applies to type=\"raytracer\"",
               true},
          Case{R"(type="sppm" indirect="irradiance_cache")",
               "indirect=\"irradiance_cache\" applies to", true},
          Case{R"(type="photon" indirect="irradiance_cache" mode="direct_visualisation")",
               "final-gather mode", false},
          Case{R"(type="path" indirect="irradiance_cache" cache_secondary="photon")",
               "cache_secondary=\"photon\" applies to", true}}) {
        INFO(c.renderer);
        const std::string xml = std::string(R"(<scene>
<objects><sphere radius="1"><center x="0" y="0" z="0"/><material type="lambert"/></sphere></objects>
<renderer )") + c.renderer + R"(/>
<film width="4" height="4"/>
<camera><eye x="0" y="0" z="-5"/><target x="0" y="0" z="0"/></camera></scene>)";
        // The <renderer> element is on line 3 of the file.
        if (c.warning) {
            const RenderSettings r = render_settings(parse_scene(xml, "rules.xml", "."));
            REQUIRE(r.warnings.size() == 1);
            CHECK_THAT(r.warnings[0],
                       Catch::Contains("rules.xml:3:") && Catch::Contains(c.message));
        } else {
            CHECK_THROWS_WITH(render_settings(parse_scene(xml, "rules.xml", ".")),
                              Catch::Contains("rules.xml:3:") && Catch::Contains(c.message));
        }
    }
}

TEST_CASE("A scene written for one integrator renders with another: its settings are warnings",
          "[registry][cli]") {
    // cornell-diffuse.xml is written for path; the switch is the issue's example.
    test::TempDir dir;
    const test::FotonRun r =
        test::run_foton("render " + test::source_path("scenes/cornell-diffuse.xml") +
                        " --integrator vcm --set rr_depth=3 --width 16 --height 16 --spp 1 -o " +
                        dir.file("v.exr"));
    CHECK(r.code == 0);
    CHECK_THAT(r.output, Catch::Contains("warning: --set:0: ") &&
                             Catch::Contains("rr_depth does not apply; ignored by type=\"vcm\""));
    CHECK(std::filesystem::exists(dir.file("v.exr")));
    // A key no integrator knows is still an error.
    CHECK(test::run_foton("render " + test::source_path("scenes/cornell-diffuse.xml") +
                          " --set rr_dept=3 --width 16 --height 16 -o " + dir.file("w.exr"))
              .code == 2);
}
