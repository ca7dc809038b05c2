// The foton command line as a user meets it: exit codes, messages, and no half-written
// images after bad input.
#include <sys/wait.h>
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "test_util.h"

namespace {
struct Run {
    int code;
    std::string output;
};

Run run(const std::string& args) {
    const std::string cmd = std::string(FOTON_BINARY) + " " + args + " 2>&1";
    FILE* p = popen(cmd.c_str(), "r");
    std::string out;
    char buf[4096];
    while (std::size_t n = std::fread(buf, 1, sizeof buf, p)) out.append(buf, n);
    const int status = pclose(p);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}
}  // namespace

TEST_CASE("foton --version and info", "[cli]") {
    const Run v = run("--version");
    CHECK(v.code == 0);
    CHECK_THAT(v.output, Catch::Contains("foton"));
    const Run i = run("info " + foton::test::source_path("scenes/bunny.xml"));
    CHECK(i.code == 0);
    CHECK_THAT(i.output, Catch::Contains("69453"));  // bunny + the floor quad
}

TEST_CASE("foton render writes EXR and PNG", "[cli]") {
    foton::test::TempDir dir;
    const Run r = run("render " + foton::test::source_path("scenes/cornell-box.xml") +
                      " --width 32 --height 32 --spp 1 --threads 2 --accel embree -q -o " +
                      dir.file("cb.exr") + " --stats-json " + dir.file("s.json"));
    CHECK(r.code == 0);
    CHECK(std::filesystem::file_size(dir.file("cb.exr")) > 0);
    CHECK(std::filesystem::file_size(dir.file("cb.png")) > 0);
    std::ifstream js(dir.file("s.json"));
    std::string json((std::istreambuf_iterator<char>(js)), std::istreambuf_iterator<char>());
    CHECK_THAT(json, Catch::Contains("\"camera_rays\": 1024"));
}

TEST_CASE("bad input: exit code 2, file:line message, no image", "[cli][bad-input]") {
    foton::test::TempDir dir;
    const std::string scene = dir.file("bad.xml");
    std::ofstream(scene) << "<scene>\n<film/>\n<camera><eye x=\"0\" y=\"0\" z=\"1\"/>"
                            "<target x=\"0\" y=\"0\" z=\"0\"/></camera>\n<objects>\n"
                            "<sphere radius=\"-2\"><center x=\"0\" y=\"0\" z=\"0\"/>"
                            "<material type=\"matte\"/></sphere>\n</objects></scene>\n";
    const Run r = run("render " + scene + " -o " + dir.file("out.exr"));
    CHECK(r.code == 2);
    CHECK_THAT(r.output, Catch::Contains(scene + ":5: sphere radius must be positive"));
    CHECK_FALSE(std::filesystem::exists(dir.file("out.exr")));
    CHECK_FALSE(std::filesystem::exists(dir.file("out.png")));
    int files = 0;
    for ([[maybe_unused]] auto& e : std::filesystem::directory_iterator(dir.path())) ++files;
    CHECK(files == 1);  // only the scene itself

    CHECK(run("render " + dir.file("missing.xml")).code == 2);
    CHECK(run("render " + scene + " --accel octree").code == 2);
    CHECK(run("render " + foton::test::source_path("scenes/cornell-box.xml") + " -o x.png").code ==
          2);
    CHECK(run("render --no-such-flag").code == 2);
    CHECK(run("").code == 2);
}
