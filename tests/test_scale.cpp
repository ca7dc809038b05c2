// `foton scale`: the scaling metrics on runs whose answers are known (Amdahl's law), the
// thread-count list, and the command on small scenes: its JSON's fields, its plot, and the
// images of the sweep, bit-identical for every thread count.
#include <sys/wait.h>
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>

#include <nlohmann/json.hpp>

#include "engine/app/scale_metrics.h"
#include "engine/core/cpu_topology.h"
#include "engine/core/error.h"
#include "engine/film/image_io.h"
#include "test_util.h"

using namespace foton;

namespace {

app::ScaleRun run_of(int threads, double wall, std::vector<std::pair<std::string, double>> st) {
    app::ScaleRun r;
    r.threads = threads;
    r.wall_seconds = wall;
    r.samples = 1000;
    r.stage_thread_seconds = std::move(st);
    return r;
}

std::string slurp(const std::string& path) {
    std::ifstream in(path);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

int shell(const std::string& cmd) {
    const int status = std::system((cmd + " > /dev/null 2>&1").c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST_CASE("scaling metrics: Amdahl's law gives back its serial fraction", "[scale][fast]") {
    // T(n) = 10 (0.1 + 0.9 / n): Karp-Flatt is exactly 0.1 at every n. Stage "trace" keeps
    // its thread-seconds (efficiency 1), "balance" is serial: its wall time, times the
    // threads it holds, grows with n.
    app::ScaleStudy s;
    s.args.repeats = 3;
    for (const int n : {1, 2, 4})
        for (const double jitter : {0.0, 0.2, -0.1}) {
            const double wall = 10.0 * (0.1 + 0.9 / n);
            // The median of the three is the exact time.
            s.runs.push_back(
                run_of(n, wall + jitter, {{"trace", 9.0 + jitter}, {"balance", 1.0 * n + jitter}}));
        }
    app::summarise(s);
    REQUIRE(s.points.size() == 3);
    for (const app::ScalePoint& p : s.points) {
        INFO(p.threads << " threads");
        const double n = p.threads;
        CHECK(p.wall_median == Approx(10.0 * (0.1 + 0.9 / n)));
        CHECK(p.wall_min == Approx(p.wall_median - 0.1));
        CHECK(p.wall_max == Approx(p.wall_median + 0.2));
        CHECK(p.speedup == Approx(1.0 / (0.1 + 0.9 / n)));
        CHECK(p.efficiency == Approx(p.speedup / n));
        if (p.threads > 1) CHECK(p.karp_flatt == Approx(0.1));
        REQUIRE(p.stage_efficiency.size() == 2);
        CHECK(p.stage_efficiency[0].second == Approx(1.0));
        CHECK(p.stage_efficiency[1].second == Approx(1.0 / n));
    }
    CHECK(s.worst_stage == "balance");

    // Weak scaling: n times the work in the same time is efficiency 1.
    app::ScaleStudy w;
    w.args.weak = true;
    for (const int n : {1, 2, 4}) w.runs.push_back(run_of(n, 5.0, {{"trace", 5.0 * n}}));
    app::summarise(w);
    for (const app::ScalePoint& p : w.points) {
        CHECK(p.speedup == Approx(p.threads));
        CHECK(p.efficiency == Approx(1.0));
        CHECK(p.stage_efficiency[0].second == Approx(1.0));
    }
}

TEST_CASE("scaling study: thread counts", "[scale][fast]") {
    CHECK(app::thread_counts("", 6) == std::vector<int>{1, 2, 4, 6});
    CHECK(app::thread_counts("all", 8) == std::vector<int>{1, 2, 4, 8});
    CHECK(app::thread_counts("all", 1) == std::vector<int>{1});
    CHECK(app::thread_counts("1,3,12", 2) == std::vector<int>{1, 3, 12});
    CHECK_THROWS_WITH(app::thread_counts("2,1", 4), Catch::Contains("must increase"));
    CHECK_THROWS_AS(app::thread_counts("0", 4), InputError);
    CHECK_THROWS_AS(app::thread_counts("1,x", 4), InputError);
    const CpuTopology t = cpu_topology();
    CHECK(t.logical >= 1);
    CHECK(int(t.cpu_order.size()) == t.logical);
    CHECK(t.cores * t.threads_per_core >= t.logical);
}

TEST_CASE("foton scale: table, JSON, plot, and identical images at every thread count",
          "[scale][cli]") {
    test::TempDir dir;
    const std::string foton = FOTON_BINARY;
    struct Case {
        const char* scene;
        const char* flags;
    };
    const Case cases[] = {
        {"scenes/cornell-diffuse.xml", "--integrator path --spp 2"},
        {"scenes/cornell-caustics.xml",
         "--integrator photon --spp 1 --set global_photons=20000 --set caustic_photons=5000"},
        {"scenes/cornell-caustics.xml", "--integrator sppm --spp 2 --set photons_per_pass=5000"},
        {"scenes/cornell-diffuse.xml", "--integrator path --set indirect=irradiance_cache --spp 1"},
    };
    int k = 0;
    for (const Case& c : cases) {
        INFO(c.scene << " " << c.flags);
        const std::string stem = std::string("s").append(std::to_string(k++));
        const std::string json = dir.file(stem + ".json"), svg = dir.file(stem + ".svg");
        const int code = shell(foton + " scale " + test::source_path(c.scene) + " " + c.flags +
                               " --width 24 --height 24 --threads 1,2,3 --repeats 2 --pin -o " +
                               json + " --plot " + svg);
        REQUIRE(code == 0);
        const nlohmann::json j = nlohmann::json::parse(slurp(json));
        CHECK(j["schema"] == "foton-scale");
        for (const char* key :
             {"cpu", "sockets", "cores", "threads_per_core", "numa_nodes", "simd", "simd_width"})
            CHECK(j["machine"].contains(key));
        CHECK(j["build"].contains("git_commit"));
        CHECK(j["scene"].contains("fnv1a"));
        CHECK(j["settings"].contains("renderer"));
        CHECK(j["settings"]["mode"] == "strong");
        CHECK(j["settings"]["pinned"] == true);
        CHECK(j["images_identical"] == true);
        REQUIRE(j["points"].size() == 3);
        CHECK(j["points"][2]["threads"] == 3);
        CHECK(j["points"][2].contains("wall_median"));
        CHECK(j["points"][2].contains("karp_flatt"));
        CHECK(j["points"][2]["stage_efficiency"].is_object());
        CHECK(!j["points"][2]["stage_efficiency"].empty());
        // Six runs, one image.
        REQUIRE(j["runs"].size() == 6);
        for (const nlohmann::json& r : j["runs"])
            CHECK(r["image_fnv1a"] == j["runs"][0]["image_fnv1a"]);
        CHECK(slurp(svg).rfind("<svg", 0) == 0);
    }
    // Bad input: the usual message and exit code 2, before any render.
    CHECK(shell(foton + " scale " + test::source_path("scenes/cornell-diffuse.xml") +
                " --threads 2,1") == 2);
    CHECK(shell(foton + " scale " + test::source_path("scenes/cornell-diffuse.xml") +
                " --weak --time 1") == 2);
}

TEST_CASE("foton render --pin: the same image, and the statistics say it was pinned",
          "[scale][cli]") {
    test::TempDir dir;
    const std::string render = std::string(FOTON_BINARY) + " render " +
                               test::source_path("scenes/cornell-box.xml") +
                               " --integrator path --spp 2 --width 32 --height 24 -q --threads 2";
    REQUIRE(shell(render + " -o " + dir.file("free.exr")) == 0);
    REQUIRE(shell(render + " --pin -o " + dir.file("pinned.exr") + " --stats-json " +
                  dir.file("pinned.json")) == 0);
    const Film a = read_exr(dir.file("free.exr")), b = read_exr(dir.file("pinned.exr"));
    REQUIRE(a.pixels.size() == b.pixels.size());
    CHECK(std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(RGB)) == 0);
    CHECK_THAT(slurp(dir.file("pinned.json")), Catch::Contains("\"pinned\": true"));
}
