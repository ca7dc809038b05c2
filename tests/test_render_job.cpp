// The render job every front-end makes and the metadata it writes (app/render_job.h): an EXR
// saved from `foton serve`'s page carries the same attributes as the command line's, with the
// page's request in the command line's words, and the page's requests meet the command line's
// checks.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

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
        if (const auto bytes = session.exr()) exr = *bytes;
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

    // Defect 13: 50 requests at once for the image once copied the film 50 times and encoded
    // it 50 times (805 MB each at 8192²). They now share one encoding per image and exposure,
    // and the EXR is one buffer whatever the number of readers.
    std::vector<std::shared_ptr<const std::string>> pngs(50);
    std::vector<std::thread> readers;
    for (std::size_t i = 0; i < pngs.size(); ++i)
        readers.emplace_back([&, i] { pngs[i] = session.png(0.f); });
    for (std::thread& t : readers) t.join();
    REQUIRE(pngs[0]);
    CHECK(pngs[0]->size() > 8);
    for (const auto& p : pngs) CHECK(p.get() == pngs[0].get());
    const auto brighter = session.png(1.f);
    CHECK(brighter.get() != pngs[0].get());
    CHECK(session.exr().get() == session.exr().get());
}

TEST_CASE("foton serve's requests meet the command line's checks", "[cli][serve]") {
    // The state a request ends in, once the session has finished with it.
    auto outcome = [](const app::SessionRequest& r) {
        app::RenderSession session;
        std::string error;
        REQUIRE(session.start(r, error));
        nlohmann::json status;
        for (int i = 0; i < 600; ++i) {
            status = nlohmann::json::parse(session.status_json());
            if (status["state"] != "running") break;
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        return status;
    };
    app::SessionRequest r;
    r.scene_path = test::source_path("scenes/cornell-diffuse.xml");
    r.width = r.height = 8;
    r.threads = 1;
    CHECK(outcome(r)["state"] == "done");
    // 32768 x 32768 passes each side's limit but not the image's (the command line's check).
    app::SessionRequest big = r;
    big.width = big.height = 32768;
    nlohmann::json s = outcome(big);
    CHECK(s["state"] == "error");
    CHECK_THAT(s["message"].get<std::string>(), Catch::Contains("pixels"));
    for (float t : {std::nanf(""), -1.f, std::numeric_limits<float>::infinity()}) {
        app::SessionRequest timed = r;
        timed.time = t;
        s = outcome(timed);
        INFO(t);
        CHECK(s["state"] == "error");
        CHECK_THAT(s["message"].get<std::string>(), Catch::Contains("--time"));
    }
    app::SessionRequest bad = r;
    bad.set["max_depth"] = "deep";
    s = outcome(bad);
    CHECK(s["state"] == "error");
    CHECK_THAT(s["message"].get<std::string>(), Catch::Contains("max_depth"));
}
