// Progress reporting: which task the line shows, the line's format, and the line itself under
// a pseudo-terminal for every integrator (and never when stderr is a file).
#include <pty.h>
#include <sys/wait.h>
#include <unistd.h>
#include <catch2/catch.hpp>
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "engine/app/progress_line.h"
#include "engine/core/progress.h"
#include "test_util.h"

using namespace foton;

TEST_CASE("Progress shows the sized task expected to end last", "[progress]") {
    Progress p;
    CHECK_FALSE(p.view());
    const int unknown = p.begin("balance", 0);
    REQUIRE(p.view());
    CHECK(p.view()->name == "balance");
    CHECK(p.view()->fraction < 0.0);
    const int a = p.begin("photons-global", 100);
    const int b = p.begin("photons-caustic", 100);
    p.advance(a, 50);
    p.advance(b, 10);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    // Both sized tasks began at about the same time; the caustic one is further from done.
    Progress::View v = *p.view();
    CHECK(v.name == "photons-caustic");
    CHECK(v.fraction == Approx(0.1));
    CHECK(v.others == 2);
    p.end(b);
    v = *p.view();
    CHECK(v.name == "photons-global");
    CHECK(v.fraction == Approx(0.5));
    CHECK(v.eta > 0.0);
    p.end(a);
    p.end(unknown);
    CHECK_FALSE(p.view());
    // A time budget's fraction is the clock's.
    const int t = p.begin_budget("passes", 10.0, Progress::Clock::now() - std::chrono::seconds(5));
    CHECK(p.view()->fraction == Approx(0.5).margin(0.01));
    CHECK(p.view()->eta == Approx(5.0).margin(0.1));
    p.end(t);
    // More tasks than slots: the rest go unreported, harmlessly.
    std::vector<int> slots;
    for (int i = 0; i < 40; ++i) slots.push_back(p.begin("task", 1));
    CHECK(slots.back() == -1);
    p.advance(-1, 5);
    for (int s : slots) p.end(s);
    CHECK_FALSE(p.view());
}

TEST_CASE("the progress line fits 79 columns in every form", "[progress]") {
    Progress::View v;
    v.name = "a-very-long-task-name-that-goes-on";
    v.elapsed = 12345.6;
    CHECK(app::ProgressLine::format(v).size() <= 79);
    CHECK_THAT(app::ProgressLine::format(v), Catch::Contains("..."));
    v.fraction = 0.5;
    v.eta = 1e9;
    v.others = 3;
    const std::string line = app::ProgressLine::format(v);
    CHECK(line.size() <= 79);
    CHECK_THAT(line, Catch::Contains(" 50.0%"));
    CHECK_THAT(line, Catch::Contains("ETA"));
    CHECK_THAT(line, Catch::Contains("+3"));
}

namespace {

// Runs foton with its stdout and stderr on a pseudo-terminal; returns what it wrote.
std::string run_on_pty(const std::string& args, int& code) {
    int master = -1;
    const pid_t pid = forkpty(&master, nullptr, nullptr, nullptr);
    REQUIRE(pid >= 0);
    if (pid == 0) {
        const std::string cmd = std::string("exec ") + FOTON_BINARY + " " + args;
        execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
        _exit(127);
    }
    std::string out;
    char buf[4096];
    for (;;) {
        const ssize_t n = read(master, buf, sizeof buf);
        if (n > 0) {
            out.append(buf, std::size_t(n));
        } else if (n < 0 && errno == EINTR) {
            continue;
        } else {
            break;  // EIO: the child closed the terminal
        }
    }
    close(master);
    int status = 0;
    waitpid(pid, &status, 0);
    code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return out;
}

}  // namespace

TEST_CASE("progress appears for every integrator on a terminal, never in a file",
          "[progress][cli]") {
    test::TempDir dir;
    const std::string cornell = test::source_path("scenes/cornell-diffuse.xml");
    const std::string caustics = test::source_path("scenes/cornell-caustics.xml");
    struct Case {
        std::string args, phase;
    };
    const std::vector<Case> cases = {
        {cornell + " --integrator raytracer", "camera-paths"},
        {cornell + " --integrator path", "camera-paths"},
        {cornell + " --integrator distributed", "camera-paths"},
        {cornell + " --integrator path --passes 3", "camera-paths"},
        {cornell + " --integrator path --time 0.2", "camera-paths"},
        {cornell + " --integrator path --adaptive 0.1", "adaptive-sampling"},
        {cornell + " --integrator light", "light-paths"},
        {caustics + " --integrator photon --set global_photons=2000 --set caustic_photons=2000",
         "photons-"},
        {caustics + " --integrator photon --set global_photons=2000 --set caustic_photons=0 --set "
                    "indirect=irradiance_cache",
         "cache-fill-records"},
        {caustics + " --integrator sppm --passes 2", "sppm passes"},
        {caustics + " --integrator ppm --passes 2", "ppm passes"},
    };
    for (const Case& c : cases) {
        INFO(c.args);
        const std::string common = " --width 24 --height 24 --spp 1 -o " + dir.file("p.exr");
        int code = -1;
        const std::string out = run_on_pty("render " + c.args + common, code);
        CHECK(code == 0);
        CHECK_THAT(out, Catch::Contains(c.phase));
        CHECK_THAT(out, Catch::Contains("\r"));
        // The line is blanked before the summary: nothing of it shares the summary's line.
        const std::size_t summary = out.find("rendered ");
        REQUIRE(summary != std::string::npos);
        CHECK(out[summary - 1] == '\r');
        // Quiet: no progress.
        const std::string quiet = run_on_pty("render " + c.args + common + " -q", code);
        CHECK(code == 0);
        CHECK(quiet.find('\r') == std::string::npos);
        // Stderr to a file: none there either.
        const std::string err = dir.file("err.txt");
        const std::string cmd =
            std::string(FOTON_BINARY) + " render " + c.args + common + " >/dev/null 2>" + err;
        CHECK(std::system(cmd.c_str()) == 0);
        std::ifstream in(err);
        const std::string text((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
        CHECK(text.find('\r') == std::string::npos);
        CHECK(text.find(c.phase) == std::string::npos);
    }
}
