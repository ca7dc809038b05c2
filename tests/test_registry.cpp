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
    };
    for (const Case& c :
         {Case{R"(type="light" adaptive="true")", "adaptive sampling applies to camera"},
          Case{R"(type="sppm" indirect="irradiance_cache")", "indirect=\"irradiance_cache\" needs"},
          Case{R"(type="photon" indirect="irradiance_cache" mode="direct_visualisation")",
               "final-gather mode"},
          Case{R"(type="path" indirect="irradiance_cache" cache_secondary="photon")",
               "no photon map"}}) {
        INFO(c.renderer);
        const std::string xml = std::string(R"(<scene>
<objects><sphere radius="1"><center x="0" y="0" z="0"/><material type="lambert"/></sphere></objects>
<renderer )") + c.renderer + R"(/>
<film width="4" height="4"/>
<camera><eye x="0" y="0" z="-5"/><target x="0" y="0" z="0"/></camera></scene>)";
        // The <renderer> element is on line 3 of the file.
        CHECK_THROWS_WITH(render_settings(parse_scene(xml, "rules.xml", ".")),
                          Catch::Contains("rules.xml:3:") && Catch::Contains(c.message));
    }
}
