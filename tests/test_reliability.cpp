// Issue 19's cases, each as written by the attacker or careless user who found it: exit 2
// with a clear message (or a correct render), no crash, no NaN, no stray or clobbered file.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <thread>
#include <vector>

#include "engine/accel/intersector.h"
#include "engine/core/error.h"
#include "engine/film/image_io.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/render.h"
#include "test_util.h"

using namespace foton;
namespace fs = std::filesystem;

namespace {

using Run = test::FotonRun;
Run foton_cli(const std::string& args) {
    return test::run_foton(args);
}

std::string scene_with(const std::string& material, const std::string& objects_extra = "") {
    return R"(<scene><film width="16" height="16"/>
<camera><eye x="0" y="0" z="5"/><target x="0" y="0" z="0"/></camera>
<lights><point><position x="2" y="3" z="4"/><color r="20" g="20" b="20"/></point></lights>
<objects>)" +
           objects_extra + R"(<sphere radius="1"><center x="0" y="0" z="0"/>)" + material +
           "</sphere></objects></scene>\n";
}

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

TEST_CASE("reliability: nested mixes end with an error, not a stack overflow",
          "[reliability][fast]") {
    test::TempDir dir;
    std::string mix;
    for (int i = 0; i < 20000; ++i) mix += R"(<material type="mix">)";
    mix += R"(<material type="lambert"/>)";
    for (int i = 0; i < 20000; ++i) mix += "</material>";
    std::ofstream(dir.file("deep.xml")) << scene_with(mix);
    for (const char* cmd : {"info ", "render -q --width 4 --height 4 -o "}) {
        const std::string out = std::string(cmd).rfind("render", 0) == 0
                                    ? dir.file("o.exr") + " " + dir.file("deep.xml")
                                    : dir.file("deep.xml");
        const Run r = foton_cli(cmd + out);
        CHECK(r.code == 2);
        CHECK_THAT(r.output, Catch::Contains("deep.xml:4: mixes nest at most 16 deep"));
    }
}

TEST_CASE("reliability: thread counts beyond the limit are bad input", "[reliability][fast]") {
    const std::string scene = test::source_path("scenes/cornell-diffuse.xml");
    for (const char* a :
         {"--threads 70000", "--set num_threads=70000", "--set num_threads=3e9", "--threads -3"}) {
        INFO(a);
        const Run r = foton_cli("render " + scene + " --width 8 --height 8 -q -o /dev/null " + a);
        CHECK(r.code == 2);
        CHECK_THAT(r.output, Catch::Contains("num_threads' must be an integer in [0, 4096]"));
    }
    TestScene s = load_scene(scene);
    s.set_resolution(4, 4);
    const auto accel = make_intersector(s, AccelType::Bvh, 1);
    RenderOptions opt;
    opt.threads = 70000;
    CHECK_THROWS_AS(render(s, s.render, *accel, opt), InputError);
}

TEST_CASE("reliability: integers are parsed as integers, exactly, everywhere",
          "[reliability][fast]") {
    test::TempDir dir;
    const std::string scene = test::source_path("scenes/cornell-diffuse.xml");
    const std::string common = " --width 12 --height 12 -q -o ";
    for (const char* a :
         {"--set rr_depth=1e20", "--set seed=1e30", "--seed -1", "--seed 18446744073709551616",
          "--spp -1", "--spp 2.5", "--set max_depth=-1"}) {
        INFO(a);
        const Run r = foton_cli("render " + scene + common + dir.file("x.exr") + " " + a);
        CHECK(r.code == 2);
        CHECK_THAT(r.output, Catch::Contains("must be"));
        CHECK_THAT(r.output, !Catch::Contains("must not be negative"));
    }
    // Seeds that a float could not tell apart give different images, from the file, --set
    // and --seed alike; the largest seed is accepted.
    auto image = [&](const std::string& flags) {
        const std::string out = dir.file("s.exr");
        REQUIRE(foton_cli("render " + scene + common + out + " --spp 1 " + flags).code == 0);
        return read_exr(out).pixels;
    };
    auto same = [](const std::vector<RGB>& a, const std::vector<RGB>& b) {
        return std::memcmp(a.data(), b.data(), a.size() * sizeof(RGB)) == 0;
    };
    CHECK_FALSE(same(image("--set seed=16777216"), image("--set seed=16777217")));
    CHECK_FALSE(same(image("--seed 100000000"), image("--seed 100000001")));
    CHECK_FALSE(same(image("--seed 1152921504606846976"), image("--seed 1152921504606846977")));
    CHECK(same(image("--seed 100000001"), image("--set seed=100000001")));
    CHECK(same(image("--seed 1000000"), image("--set seed=1e6")));  // float notation, exact
    image("--seed 18446744073709551615");
}

TEST_CASE("reliability: outputs are checked before any work", "[reliability][fast]") {
    test::TempDir dir;
    const std::string scene = dir.file("scene.xml");
    fs::copy_file(test::source_path("scenes/cornell-diffuse.xml"), scene);
    const std::string before = slurp(scene);
    fs::create_directories(dir.file("adir.exr"));
    struct Case {
        std::string flags, message;
    };
    for (const Case& c : {Case{"-o " + dir.file("adir.exr"), "is a directory"},
                          Case{"--stats-json " + scene, "is the scene file itself"},
                          Case{"--cache-points " + scene, "is the scene file itself"},
                          Case{"--stats-json " + dir.file("adir.exr"), "is a directory"},
                          Case{"-o " + dir.file("x.png"), "output must be an .exr file"}}) {
        INFO(c.flags);
        const Run r = foton_cli("render " + scene + " --width 8 --height 8 -q " + c.flags);
        CHECK(r.code == 2);
        CHECK_THAT(r.output, Catch::Contains(c.message));
        CHECK_THAT(r.output, !Catch::Contains("internal error"));
    }
    CHECK(slurp(scene) == before);  // never overwritten
    int files = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path())) ++files;
    CHECK(files == 2);  // the scene and the directory: nothing written, no temporary left
}

TEST_CASE("reliability: a destination that cannot be written fails before the render",
          "[reliability][fast]") {
    // /proc answers access(W_OK) for root but refuses new files: probed, not trusted.
    const Run r = foton_cli("render " + test::source_path("scenes/cornell-box.xml") +
                            " --width 8 --height 8 -q -o /proc/foton-test.exr");
    CHECK(r.code == 2);
    CHECK_THAT(r.output, Catch::Contains("cannot write '/proc/foton-test.exr'"));
    CHECK_THAT(r.output, !Catch::Contains("internal error") && !Catch::Contains("rendered"));
}

TEST_CASE("reliability: a write that fails (full disk, size limit) is an error, never a file",
          "[reliability]") {
    // A file-size limit stands in for a full disk: every write past it fails with
    // EFBIG (SIGXFSZ ignored), as ENOSPC would. Nothing may be left under the output's name,
    // no temporary either, and foton must not say "wrote".
    test::TempDir dir;
    // bash's ulimit -f counts KiB.
    auto limited = [&](int kib, const std::string& args) {
        const std::string cmd = "bash -c 'trap \"\" XFSZ; ulimit -f " + std::to_string(kib) +
                                "; exec " + std::string(FOTON_BINARY) + " " + args + "' 2>&1";
        FILE* p = popen(cmd.c_str(), "r");
        std::string out;
        char buf[4096];
        while (std::size_t n = std::fread(buf, 1, sizeof buf, p)) out.append(buf, n);
        const int status = pclose(p);
        return Run{WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
    };
    const std::string box = test::source_path("scenes/cornell-box.xml");
    const Run big =
        limited(4, "render " + box + " --width 256 --height 256 --spp 1 -o " + dir.file("a.exr"));
    CHECK(big.code == 2);
    CHECK_THAT(big.output, Catch::Contains("a.exr: cannot write: File too large"));
    CHECK_THAT(big.output, !Catch::Contains("wrote"));
    // A small image (1.4 KB) fits in 2 KiB; its statistics JSON (3 KB) is checked as strictly.
    const Run small = limited(2, "render " + box + " --width 4 --height 4 --spp 1 -o " +
                                     dir.file("b.exr") + " --stats-json " + dir.file("s.json"));
    CHECK(small.code == 2);
    CHECK_THAT(small.output, Catch::Contains("s.json: cannot write: File too large"));
    int files = 0;
    for (const auto& e : fs::directory_iterator(dir.path())) {
        INFO(e.path());
        CHECK(e.path().filename().string().rfind(".", 0) != 0);  // no temporary left
        CHECK(e.path().extension() != ".json");                  // no partial JSON
        ++files;
    }
    CHECK(files <= 2);  // b.exr and its preview at most
}

TEST_CASE("reliability: bad paths and sizes are bad input at their line", "[reliability][fast]") {
    test::TempDir dir;
    // A symlink loop and an over-long name as mesh files; a FIFO and a device as scenes.
    fs::create_symlink(dir.file("loop_b"), dir.file("loop_a"));
    fs::create_symlink(dir.file("loop_a"), dir.file("loop_b"));
    const std::string longname(5000, 'n');
    for (const auto& [src, message] :
         {std::pair{dir.file("loop_a"), "Too many levels of symbolic links"},
          std::pair{longname, "File name too long"}}) {
        std::ofstream(dir.file("m.xml"))
            << scene_with(R"(<material type="lambert"/>)", "<triangle_mesh src=\"" + src + "\"/>");
        const Run r = foton_cli("info " + dir.file("m.xml"));
        CHECK(r.code == 2);
        CHECK_THAT(r.output, Catch::Contains("m.xml:4: cannot read mesh file"));
        CHECK_THAT(r.output, Catch::Contains(message));
        CHECK(r.output.size() < 3000);  // the long name is cut in the message
    }
    REQUIRE(mkfifo(dir.file("fifo.xml").c_str(), 0600) == 0);
    for (const std::string& s :
         {dir.file("fifo.xml"), std::string("/dev/zero"), dir.path().string()}) {
        const Run r = foton_cli("info " + s);
        CHECK(r.code == 2);
        CHECK_THAT(r.output, Catch::Contains("cannot read scene file"));
    }
    const std::string scene = test::source_path("scenes/cornell-diffuse.xml");
    for (const char* a : {"--width 40000", "--width 20000 --height 20000", "--height 0"}) {
        const Run r = foton_cli("render " + scene + " -q -o " + dir.file("big.exr") + " " + a);
        CHECK(r.code == 2);
        CHECK_THAT(r.output, !Catch::Contains("bad_alloc"));
    }
    // A 1 MB attribute with control bytes: the message is short and prints no raw control.
    std::string value(1 << 20, 'x');
    value[10] = '\x1b';
    std::string text = scene_with("<material type=\"lambert\"/>");
    text.replace(text.find("radius=\"1\""), 10, "radius=\"" + value + "\"");
    std::ofstream(dir.file("v.xml")) << text;
    const Run v = foton_cli("info " + dir.file("v.xml"));
    CHECK(v.code == 2);
    CHECK(v.output.size() < 3000);
    CHECK(v.output.find('\x1b') == std::string::npos);
    CHECK_THAT(v.output, Catch::Contains("\\x1b"));
}

TEST_CASE("reliability: every accepted material parameter renders without NaN",
          "[reliability][fast]") {
    test::TempDir dir;
    // Beyond the documented limits: bad input.
    for (const char* m :
         {R"(<material type="phong" exp="1e8"><base_color r="0.5" g="0.5" b="0.5"/></material>)",
          R"(<material type="microfacet" distribution="blinn" exponent="1e20"/>)",
          R"(<material type="conductor" preset="gold" roughness="1e-30"/>)",
          R"(<material type="microfacet" distribution="beckmann" roughness="1e-10"/>)",
          R"(<material type="lambert"><reflectance r="1.5" g="0.5" b="0.5"/></material>)",
          R"(<material type="oren_nayar"><reflectance r="0.5" g="2" b="0.5"/></material>)"}) {
        INFO(m);
        std::ofstream(dir.file("m.xml")) << scene_with(m);
        const Run r = foton_cli("info " + dir.file("m.xml"));
        CHECK(r.code == 2);
        CHECK_THAT(r.output, Catch::Contains("m.xml:"));
    }
    // At the limits: finite pixels with every integrator that reads them.
    for (const char* m :
         {R"(<material type="phong" exp="1e6"><base_color r="0.5" g="0.5" b="0.5"/></material>)",
          R"(<material type="microfacet" distribution="blinn" exponent="1e6"/>)",
          R"(<material type="microfacet" distribution="blinn" roughness="0.002"/>)",
          R"(<material type="conductor" preset="gold" roughness="0.002"/>)",
          R"(<material type="microfacet" distribution="beckmann" roughness="0.002"/>)",
          R"(<material type="microfacet" distribution="ashikhmin_shirley" nu="1e6" nv="0.001"/>)",
          R"(<material type="lambert"><reflectance r="1" g="1" b="1"/></material>)"}) {
        INFO(m);
        std::ofstream(dir.file("m.xml")) << scene_with(m);
        for (const char* type : {"raytracer", "path", "light", "photon"}) {
            INFO(type);
            const Run r = foton_cli("render " + dir.file("m.xml") + " -q --spp 2 --integrator " +
                                    type + " -o " + dir.file("m.exr"));
            REQUIRE(r.code == 0);
            int bad = 0;
            for (const RGB& p : read_exr(dir.file("m.exr")).pixels)
                bad += !(std::isfinite(p.r) && std::isfinite(p.g) && std::isfinite(p.b));
            CHECK(bad == 0);
        }
    }
}

namespace {
// Starts foton with `args` (no shell), its output to /dev/null.
pid_t spawn_foton(const std::vector<std::string>& args) {
    const pid_t pid = fork();
    if (pid == 0) {
        std::vector<char*> argv{const_cast<char*>(FOTON_BINARY)};
        for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        freopen("/dev/null", "w", stdout);
        freopen("/dev/null", "w", stderr);
        execv(FOTON_BINARY, argv.data());
        _exit(127);
    }
    return pid;
}

int wait_exit(pid_t pid) {
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The EXR's per-pixel sample counts, when it has them.
std::optional<std::vector<uint32_t>> samples_channel(const std::string& path) {
    Imf::InputFile file(path.c_str());
    if (!file.header().channels().findChannel("samples")) return std::nullopt;
    const Imath::Box2i dw = file.header().dataWindow();
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    std::vector<uint32_t> counts(std::size_t(w) * std::size_t(h));
    Imf::FrameBuffer fb;
    char* base = reinterpret_cast<char*>(counts.data()) -
                 (std::ptrdiff_t(dw.min.x) + std::ptrdiff_t(dw.min.y) * w) * 4;
    fb.insert("samples", Imf::Slice(Imf::UINT, base, 4, std::size_t(w) * 4));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    return counts;
}

int hidden_files(const std::string& dir) {
    int n = 0;
    for (const auto& e : fs::directory_iterator(dir)) n += e.path().filename().string()[0] == '.';
    return n;
}
}  // namespace

TEST_CASE("reliability: Ctrl-C keeps the image so far, a second one quits at once",
          "[reliability]") {
    test::TempDir dir;
    const std::string scene = test::source_path("scenes/cornell-diffuse.xml");
    // A 30 s progressive render and a long single pass: the first signal ends each soon after,
    // with a valid image that says how many samples it holds.
    for (const std::vector<std::string>& extra :
         {std::vector<std::string>{"--time", "30", "--width", "32", "--height", "32"},
          std::vector<std::string>{"--spp", "4000", "--width", "256", "--height", "256"}}) {
        std::vector<std::string> args = {"render", scene, "-q", "-o", dir.file("i.exr")};
        args.insert(args.end(), extra.begin(), extra.end());
        const auto t0 = std::chrono::steady_clock::now();
        const pid_t pid = spawn_foton(args);
        std::this_thread::sleep_for(std::chrono::milliseconds(1500));
        kill(pid, SIGINT);
        CHECK(wait_exit(pid) == 130);
        CHECK(std::chrono::steady_clock::now() - t0 < std::chrono::seconds(20));
        const Film f = read_exr(dir.file("i.exr"));
        CHECK(f.width > 0);
        std::string interrupted, spp, unfinished;
        for (const auto& [k, v] : read_exr_attributes(dir.file("i.exr"))) {
            if (k == "foton:interrupted") interrupted = v;
            if (k == "foton:samples") spp = v;
            if (k == "foton:unfinishedPixels") unfinished = v;
        }
        CHECK(interrupted == "true");
        CHECK(std::stod(spp) > 0.0);
        // The long pass was cut: its `samples` channel has 0 where no sample arrived, and the
        // attribute counts those pixels. A progressive render has all of its earlier passes.
        const std::optional<std::vector<uint32_t>> counts = samples_channel(dir.file("i.exr"));
        if (extra[0] == "--spp") {
            REQUIRE(counts);
            const auto none = std::count(counts->begin(), counts->end(), 0u);
            CHECK(none > 0);
            CHECK(none < long(counts->size()));
            CHECK(unfinished == std::to_string(none));
            // A tile in flight finished: a pixel has all its samples or none.
            const uint32_t most = *std::max_element(counts->begin(), counts->end());
            CHECK(std::count(counts->begin(), counts->end(), most) + none == long(counts->size()));
        } else if (counts) {
            // The pass in flight was cut: its finished tiles hold one sample more.
            const auto [lo, hi] = std::minmax_element(counts->begin(), counts->end());
            CHECK(*lo >= 1u);
            CHECK(*hi == *lo + 1);
            CHECK(unfinished.empty());
        }
        CHECK(hidden_files(dir.path()) == 0);
        fs::remove(dir.file("i.exr"));
    }
    // Photon tracing does not stop between passes: the second signal ends the process.
    const pid_t pid = spawn_foton({"render", test::source_path("scenes/cornell-caustics.xml"),
                                   "--integrator", "photon", "--set", "global_photons=2000000000",
                                   "--width", "8", "--height", "8", "-q", "-o", dir.file("p.exr")});
    // Long enough for the handler to be installed on a loaded machine (at 800 ms the first
    // signal once came before it, under ctest -j2, and killed the process outright).
    std::this_thread::sleep_for(std::chrono::milliseconds(2000));
    const auto t0 = std::chrono::steady_clock::now();
    kill(pid, SIGTERM);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    kill(pid, SIGINT);
    CHECK(wait_exit(pid) == 130);
    CHECK(std::chrono::steady_clock::now() - t0 < std::chrono::seconds(3));
    CHECK_FALSE(fs::exists(dir.file("p.exr")));
    CHECK(hidden_files(dir.path()) == 0);
}
