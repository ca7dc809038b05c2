// The integrator table (transport/registry/integrators.h) is the one list of integrators:
// names and aliases resolve, the capability wording of error messages comes from it, and the
// scene format's documentation and the command line's help cover every row.
#include <catch2/catch.hpp>

#include <fstream>
#include <set>
#include <sstream>
#include <string>

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
