// One render across MPI ranks (issue 16): `mpirun -np N foton render` makes the image of one
// process bit for bit, for every integrator that splits its work; --time stops every rank
// after the same passes; statistics come per rank and merged; bad input on any rank ends all
// of them with the message once and exit code 2.
#include <signal.h>
#include <sys/wait.h>
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <thread>

#include "engine/film/image_io.h"
#include "test_util.h"

using namespace foton;

#ifdef FOTON_HAVE_MPI

namespace {

struct Run {
    int code = -1;
    std::string err;
};

// Runs a shell command; its stderr comes back.
Run shell(const std::string& cmd, const test::TempDir& dir) {
    const std::string err = dir.file("stderr.txt");
    const int status = std::system((cmd + " > /dev/null 2> " + err).c_str());
    std::ifstream in(err);
    Run r;
    r.err.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

// mpirun as CI runs it: as root, on a machine with fewer cores than ranks, banners off.
std::string mpirun(int ranks) {
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    return "mpirun -q --oversubscribe --bind-to none -np " + std::to_string(ranks) + " ";
}

bool same_bits(const Film& a, const Film& b) {
    return a.width == b.width && a.height == b.height &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(RGB)) == 0;
}

std::size_t count(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
        ++n;
    return n;
}

std::string slurp(const std::string& path) {
    std::ifstream in(path);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace

TEST_CASE("mpirun -np 2 and 3 renders equal one process's image bit for bit", "[mpi][cli]") {
    test::TempDir dir;
    const std::string foton = std::string(FOTON_BINARY) + " render ";
    struct Case {
        const char* name;
        const char* scene;
        const char* flags;
    };
    const Case cases[] = {
        {"path", "scenes/cornell-box.xml", "--integrator path --spp 3"},
        // The variance AOV's moments gathered from the pixels' owners, the first-hit layers
        // made on rank 0.
        {"path-aov", "scenes/cornell-box.xml", "--integrator path --spp 3 --aov all"},
        // Per-strategy images: each layer's splats added by its pixels' owners.
        {"vcm-layers", "scenes/cornell-caustics.xml",
         "--integrator vcm --spp 2 --set strategy_images=3"},
        {"raytracer", "scenes/cornell-mirror.xml", "--integrator raytracer --spp 2"},
        {"light", "scenes/cornell-box.xml", "--integrator light --spp 2"},
        {"photon-fg", "scenes/cornell-caustics.xml",
         "--integrator photon --spp 1 --set mode=final_gather --set global_photons=20000 --set "
         "caustic_photons=5000"},
        {"sppm", "scenes/cornell-caustics.xml",
         "--integrator sppm --passes 3 --set photons_per_pass=8000"},
        // The stopping rule decided on rank 0 from every rank's pixels, and its bound AOV.
        {"sppm-stop", "scenes/cornell-caustics.xml",
         "--integrator sppm --passes 60 --set photons_per_pass=8000 --set stop_error=0.4"},
        {"cache", "scenes/cornell-diffuse.xml",
         "--integrator path --set indirect=irradiance_cache --spp 1"},
        {"photon-cache", "scenes/cornell-diffuse.xml",
         "--integrator photon --set indirect=irradiance_cache --set global_photons=20000 --spp 1"},
        // Light paths of the whole image for a crop window, and a thin lens (materials).
        {"bdpt", "scenes/cornell-caustics.xml", "--integrator bdpt --spp 2 --crop 0.1,0.9,0,0.7"},
        {"bpm", "scenes/cornell-caustics.xml", "--integrator bpm --spp 2"},
        {"vcm", "scenes/materials.xml", "--integrator vcm --spp 2"},
        {"vcm-kdtree", "scenes/cornell-caustics.xml",
         "--integrator vcm --spp 2 --set merge_index=kdtree"},
        // Participating media: volumetric paths, photons, light paths and bidirectional paths
        // through the fog (the smoke's grid flights in vcm).
        {"volpath", "scenes/cornell-fog.xml", "--integrator volpath --spp 2"},
        {"volpath-spectral", "scenes/cornell-fog.xml",
         "--integrator volpath --spp 2 --set spectral=true"},
        {"vpm", "scenes/cornell-fog.xml",
         "--integrator vpm --passes 2 --set photons_per_pass=6000"},
        {"light-media", "scenes/cornell-fog.xml", "--integrator light --spp 2"},
        {"bdpt-media", "scenes/cornell-fog.xml", "--integrator bdpt --spp 2"},
        {"vcm-media", "scenes/smoke.xml", "--integrator vcm --spp 1"},
    };
    for (const Case& c : cases) {
        INFO(c.name << ": " << c.flags);
        const std::string args = test::source_path(c.scene) + " " + c.flags +
                                 " --width 40 --height 32 -q -o " + dir.file(c.name);
        REQUIRE(shell(foton + args + "-1.exr --threads 2", dir).code == 0);
        const Film one = read_exr(dir.file(c.name) + "-1.exr");
        for (const int ranks : {2, 3}) {
            INFO(ranks << " ranks");
            const Run r = shell(mpirun(ranks) + foton + args + "-n.exr --threads 1", dir);
            INFO(r.err);
            REQUIRE(r.code == 0);
            CHECK(same_bits(read_exr(dir.file(c.name) + "-n.exr"), one));
            const std::string flags = c.flags;
            std::vector<std::string> channels;
            if (flags.find("--aov") != std::string::npos) channels = aov_channels(kAovAll);
            if (flags.find("strategy_images") != std::string::npos)
                channels = {"strategy_s0_t2.R", "strategy_s1_t2.G", "strategy_s2_t1.B",
                            "strategy_longer.R", "strategy_merges.G"};
            if (flags.find("stop_error") != std::string::npos)
                channels = {"ErrorBound.R", "ErrorBound.G", "ErrorBound.B"};
            if (channels.empty()) continue;
            int w = 0, h = 0;
            CHECK(read_exr_channels(dir.file(c.name) + "-n.exr", channels, w, h) ==
                  read_exr_channels(dir.file(c.name) + "-1.exr", channels, w, h));
        }
    }
}

TEST_CASE(
    "mpirun with --time: every rank runs the same passes and statistics come per rank and merged",
    "[mpi][cli]") {
    test::TempDir dir;
    const std::string foton = std::string(FOTON_BINARY) + " render ";
    const std::string args = test::source_path("scenes/cornell-box.xml") +
                             " --integrator path --width 32 --height 24 -q --threads 1";
    const std::string json = dir.file("stats.json");
    REQUIRE(shell(mpirun(2) + foton + args + " --time 0.4 -o " + dir.file("timed.exr") +
                      " --stats-json " + json,
                  dir)
                .code == 0);
    const std::string j = slurp(json);
    CHECK_THAT(j, Catch::Contains("\"mpi_ranks\": 2"));
    CHECK_THAT(j, Catch::Contains("\"rank\": 0"));
    CHECK_THAT(j, Catch::Contains("\"rank\": 1"));
    CHECK(count(j, "\"host\": \"") == 2);  // each rank says where it ran
    // Each rank's record (in the "ranks" list), then the merged one: all with the same
    // passes.
    std::vector<long> passes, samples;
    for (std::size_t at = j.find("\"passes\": "); at != std::string::npos;
         at = j.find("\"passes\": ", at + 1))
        passes.push_back(std::strtol(j.c_str() + at + 10, nullptr, 10));
    for (std::size_t at = j.find("\"samples\": "); at != std::string::npos;
         at = j.find("\"samples\": ", at + 1))
        samples.push_back(std::strtol(j.c_str() + at + 11, nullptr, 10));
    REQUIRE(passes.size() == 3);
    CHECK(passes[0] >= 1);
    CHECK(passes[1] == passes[0]);
    CHECK(passes[2] == passes[0]);
    REQUIRE(samples.size() == 3);
    CHECK(samples[2] == samples[0] + samples[1]);
    CHECK(samples[2] == 32L * 24L * passes[0]);
    // And the image is one process's after those passes.
    REQUIRE(shell(foton + args + " --passes " + std::to_string(passes[0]) + " -o " +
                      dir.file("one.exr"),
                  dir)
                .code == 0);
    CHECK(same_bits(read_exr(dir.file("timed.exr")), read_exr(dir.file("one.exr"))));
}

TEST_CASE("mpirun: bad input on every rank or on one ends all with the message shown once",
          "[mpi][cli]") {
    test::TempDir dir;
    const std::string foton = std::string(FOTON_BINARY) + " render ";
    const std::string bad = dir.file("bad.xml");
    std::ofstream(bad) << "<scene>\n  <film width=\"-4\" height=\"8\"/>\n</scene>\n";
    const std::string out = dir.file("never.exr");
    SECTION("every rank") {
        const Run r = shell(mpirun(3) + foton + bad + " -q -o " + out, dir);
        CHECK(r.code == 2);
        CHECK(count(r.err, bad + ":2:") == 1);
    }
    SECTION("only rank 1: the others wait for nothing") {
        const std::string good = test::source_path("scenes/cornell-box.xml");
        const Run r = shell(mpirun(3) + "sh -c 'if [ \"$OMPI_COMM_WORLD_RANK\" = 1 ]; then exec " +
                                foton + bad + " -q -o " + out + "; else exec " + foton + good +
                                " --width 8 --height 8 -q -o " + out + "; fi'",
                            dir);
        CHECK(r.code == 2);
        CHECK(count(r.err, bad + ":2:") == 1);
        CHECK_THAT(r.err, Catch::Contains("(on MPI rank 1)"));
    }
    SECTION("a setting the renderer rejects, found by every rank alike") {
        const Run r =
            shell(mpirun(2) + foton + test::source_path("scenes/cornell-box.xml") +
                      " --integrator vcm --set rr_depht=3 --width 8 --height 8 -q -o " + out,
                  dir);
        CHECK(r.code == 2);
        CHECK(count(r.err, "unknown setting 'rr_depht'") == 1);
    }
    std::FILE* f = std::fopen(out.c_str(), "rb");
    CHECK(f == nullptr);
    if (f) std::fclose(f);
}

TEST_CASE("mpirun: ranks that loaded different jobs stop before rendering, the difference named",
          "[mpi][cli]") {
    test::TempDir dir;
    const std::string foton = std::string(FOTON_BINARY) + " render ";
    const std::string scene = test::source_path("scenes/cornell-box.xml");
    const std::string out = dir.file("mixed.exr");
    // Rank 1 runs `theirs`, the others `ours`.
    auto split = [&](const std::string& ours, const std::string& theirs) {
        return shell(mpirun(2) + "sh -c 'if [ \"$OMPI_COMM_WORLD_RANK\" = 1 ]; then exec " + foton +
                         theirs + " -q -o " + out + "; else exec " + foton + ours + " -q -o " +
                         out + "; fi'",
                     dir);
    };
    SECTION("another width: once a silently mixed image") {
        const Run r = split(scene + " --width 16 --height 8", scene + " --width 24 --height 8");
        CHECK(r.code == 2);
        CHECK(count(r.err,
                    "MPI ranks disagree on the job: rank 1 has resolution '24x8', rank 0 "
                    "has '16x8'") == 1);
    }
    SECTION("another integrator: once a deadlock") {
        const Run r = split(scene + " --width 8 --height 8 --integrator path",
                            scene + " --width 8 --height 8 --integrator sppm --passes 2");
        CHECK(r.code == 2);
        CHECK(count(r.err, "rank 1 has integrator 'sppm', rank 0 has 'path'") == 1);
    }
    SECTION("another seed or scene file") {
        const Run seed = split(scene + " --width 8 --height 8", scene +
                                                                    " --width 8 --height 8 "
                                                                    "--seed 7");
        CHECK(seed.code == 2);
        CHECK_THAT(seed.err, Catch::Contains("MPI ranks disagree"));
        const std::string copy = dir.file("cornell-box.xml");
        std::ofstream(copy) << slurp(scene) << "<!-- another node's copy -->\n";
        const Run file = split(scene + " --width 8 --height 8", copy + " --width 8 --height 8");
        CHECK(file.code == 2);
        CHECK_THAT(file.err, Catch::Contains("rank 1 has scene file's bytes"));
    }
    std::FILE* f = std::fopen(out.c_str(), "rb");
    CHECK(f == nullptr);
    if (f) std::fclose(f);
}

TEST_CASE("mpirun: Ctrl-C on one rank stops every rank and the image says it was interrupted",
          "[mpi][cli]") {
    test::TempDir dir;
    const std::string out = dir.file("stopped.exr");
    const std::string pids = dir.file("pid");
    // Each rank leaves its process id (exec keeps it); a 60 s progressive render.
    const std::string cmd = mpirun(2) + "sh -c 'echo $$ > " + pids +
                            "$OMPI_COMM_WORLD_RANK; exec " + FOTON_BINARY + " render " +
                            test::source_path("scenes/cornell-diffuse.xml") +
                            " --integrator path --time 60 --width 48 --height 32 --threads 1 -q "
                            "-o " +
                            out + "'";
    const auto t0 = std::chrono::steady_clock::now();
    std::FILE* run = popen((cmd + " 2>&1").c_str(), "r");
    REQUIRE(run);
    long pid = 0;
    for (int i = 0; i < 200 && pid == 0; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        std::ifstream(pids + "1") >> pid;
    }
    REQUIRE(pid > 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    kill(pid_t(pid), SIGINT);
    std::string text;
    char buf[256];
    while (std::fgets(buf, sizeof buf, run)) text += buf;
    const int status = pclose(run);
    INFO(text);
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 130);
    CHECK(std::chrono::steady_clock::now() - t0 < std::chrono::seconds(30));
    std::string interrupted;
    for (const auto& [k, v] : read_exr_attributes(out))
        if (k == "foton:interrupted") interrupted = v;
    CHECK(interrupted == "true");
    CHECK(read_exr(out).width == 48);
}

#else

TEST_CASE("a build without MPI says so when mpirun starts it", "[mpi][cli]") {
    test::TempDir dir;
    const std::string cmd = "OMPI_COMM_WORLD_SIZE=2 " + std::string(FOTON_BINARY) + " render " +
                            test::source_path("scenes/cornell-box.xml") + " -q -o " +
                            dir.file("x.exr") + " 2>&1";
    const int status = std::system(cmd.c_str());
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 2);
}

#endif
