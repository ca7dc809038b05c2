// The image metadata every front-end writes (app/render_job.h): an EXR saved from `foton
// serve`'s page carries the same attributes as the command line's, with the page's request in
// the command line's words.
#include <catch2/catch.hpp>

#include <chrono>
#include <fstream>
#include <map>
#include <set>
#include <thread>

#include "engine/app/render_session.h"
#include "engine/film/image_io.h"
#include "test_util.h"

using namespace foton;

TEST_CASE("foton serve's EXR carries the command line's attributes", "[cli][serve]") {
    app::RenderSession session;
    app::SessionRequest r;
    r.scene_path = test::source_path("scenes/cornell-diffuse.xml");
    r.integrator = "path";
    r.width = 16;
    r.height = 12;
    r.spp = 2;
    r.seed = 5;
    r.threads = 1;
    std::string error;
    REQUIRE(session.start(r, error));
    std::string exr;
    for (int i = 0; i < 600 && exr.empty(); ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        exr = session.exr_bytes();
    }
    REQUIRE(!exr.empty());
    const test::TempDir dir;
    const std::string served = dir.file("served.exr");
    std::ofstream(served, std::ios::binary) << exr;
    std::map<std::string, std::string> attrs;
    for (const auto& [k, v] : read_exr_attributes(served)) attrs[k] = v;
    for (const char* key :
         {"foton:scene", "foton:integrator", "foton:samples", "foton:passes", "foton:seed",
          "foton:renderSeconds", "foton:accel", "foton:version", "foton:gitCommit",
          "foton:commandLine", "foton:settings", "foton:threads", "renderTimeSeconds",
          "samplesPerPixel", "worldToCamera", "worldToNDC"}) {
        INFO(key);
        CHECK(attrs.count(key) == 1);
    }
    CHECK(attrs["foton:samples"] == "2");
    CHECK(attrs["foton:seed"] == "5");
    CHECK_THAT(attrs["foton:commandLine"], Catch::Contains("--integrator path"));
    CHECK_THAT(attrs["foton:commandLine"], Catch::Contains("--spp 2 --seed 5"));
    CHECK_THAT(attrs["foton:settings"], Catch::Contains("type=path"));
}
