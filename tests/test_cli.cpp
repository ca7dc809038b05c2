// The foton command line as a user meets it: exit codes, messages, and no half-written
// images after bad input.
#include <stb/stb_image.h>
#include <sys/wait.h>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/core/stats.h"
#include "engine/film/image_io.h"
#include "engine/film/metrics.h"
#include "test_util.h"

namespace {
using Run = foton::test::FotonRun;
Run run(const std::string& args) {
    return foton::test::run_foton(args);
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

TEST_CASE("foton render --filter sets the pixel filter, bad ones exit 2 with no image",
          "[cli][filter]") {
    foton::test::TempDir dir;
    const std::string scene = foton::test::source_path("scenes/cornell-box.xml");
    const std::string common = " --width 16 --height 16 --spp 2 --threads 2 -q -o ";
    const Run box = run("render " + scene + common + dir.file("box.exr"));
    const Run g =
        run("render " + scene + " --filter gaussian:1.5:0.5" + common + dir.file("g.exr"));
    CHECK(box.code == 0);
    CHECK(g.code == 0);
    // The Gaussian blurs: the two images differ.
    std::ifstream a(dir.file("box.exr"), std::ios::binary), b(dir.file("g.exr"), std::ios::binary);
    const std::string ta((std::istreambuf_iterator<char>(a)), std::istreambuf_iterator<char>());
    const std::string tb((std::istreambuf_iterator<char>(b)), std::istreambuf_iterator<char>());
    CHECK(ta != tb);
    for (const char* bad : {"mitchell:2:0.3", "lanczos:4:0", "mitchell:2:2:0", "cubic",
                            "gaussian:0", "box:2:1", "gaussian:1.5:x", "triangle:99"}) {
        INFO(bad);
        const Run r = run("render " + scene + " --filter " + bad + common + dir.file("bad.exr"));
        CHECK(r.code == 2);
        CHECK_THAT(r.output, Catch::Contains("--filter"));
        CHECK_FALSE(std::filesystem::exists(dir.file("bad.exr")));
    }
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
    // A broken model given as the scene fails as a model, an image is named as what it is:
    // neither is "malformed XML".
    const std::string glb = dir.file("model.GLB"), exr = dir.file("picture.exr");
    std::ofstream(glb) << "glTF\x02";
    std::ofstream(exr) << "v/1\x01";
    const Run model = run("render " + glb + " -o " + dir.file("m.exr"));
    CHECK(model.code == 2);
    CHECK_THAT(model.output, Catch::Contains(glb + ": malformed glTF"));
    CHECK(!std::filesystem::exists(dir.file("m.exr")));
    const Run image = run("info " + exr);
    CHECK(image.code == 2);
    CHECK_THAT(image.output, Catch::Contains(exr + ": an image, not a scene"));
    CHECK_THAT(model.output + image.output, !Catch::Contains("malformed XML"));
}

TEST_CASE("foton render model.obj: a model renders as a scene of its own", "[cli]") {
    // A triangle facing +z: framed by the default camera, in front of the white sky.
    foton::test::TempDir dir;
    std::ofstream(dir.file("tri.obj")) << "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n";
    const Run r = run("render " + dir.file("tri.obj") + " --spp 4 --width 40 --height 30 -o " +
                      dir.file("tri.exr"));
    INFO(r.output);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.output, Catch::Contains("a model rendered as a scene"));
    const foton::Film img = foton::read_exr(dir.file("tri.exr"));
    REQUIRE(img.width == 40);
    // The sky (radiance 1) at the corners, the grey triangle in the middle.
    CHECK(img.at(0, 0).g == Approx(1.f).margin(1e-3));
    CHECK(img.at(39, 29).g == Approx(1.f).margin(1e-3));
    CHECK(img.at(20, 16).g < 0.9f);
    CHECK(img.at(20, 16).g > 0.05f);
}

TEST_CASE("foton render: integrators, progressive snapshots, bad integrator input", "[cli]") {
    foton::test::TempDir dir;
    const std::string cornell = foton::test::source_path("scenes/cornell-diffuse.xml");
    const Run r =
        run("render " + cornell + " --width 32 --height 32 --integrator light --spp 2 -q -o " +
            dir.file("l.exr"));
    CHECK(r.code == 0);
    CHECK(std::filesystem::exists(dir.file("l.exr")));
    const Run t =
        run("render " + cornell + " --width 32 --height 32 --time 0.3 --snapshots 0.1 -q -o " +
            dir.file("p.exr"));
    CHECK(t.code == 0);
    CHECK(std::filesystem::exists(dir.file("p.exr")));
    CHECK(std::filesystem::exists(dir.file("p-0.1s.exr")));
    CHECK(run("render " + cornell + " --integrator bidir").code == 2);
    CHECK(run("render " + cornell + " --mis cubic").code == 2);
    CHECK(run("render " + cornell + " --adaptive 0.05 --time 3").code == 2);
    // The light tracer cannot connect to an orthographic camera.
    std::ofstream(dir.file("ortho.xml"))
        << "<scene><lights><point><position x=\"0\" y=\"2\" z=\"0\"/></point></lights><objects>"
           "<sphere radius=\"1\"><center x=\"0\" y=\"0\" z=\"0\"/><material type=\"lambert\"/>"
           "</sphere></objects><film width=\"8\" height=\"8\"/><renderer type=\"light\"/>"
           "<camera type=\"orthographic\"><eye x=\"0\" y=\"0\" z=\"5\"/><target x=\"0\" y=\"0\" "
           "z=\"0\"/></camera></scene>";
    const Run o = run("render " + dir.file("ortho.xml") + " -o " + dir.file("o.exr"));
    CHECK(o.code == 2);
    CHECK_THAT(o.output, Catch::Contains("pinhole perspective camera"));
    CHECK_FALSE(std::filesystem::exists(dir.file("o.exr")));
}

TEST_CASE("foton compare: metrics, downsampled reference, masks", "[cli][compare]") {
    foton::test::TempDir dir;
    const std::string cornell = foton::test::source_path("scenes/cornell-diffuse.xml");
    REQUIRE(
        run("render " + cornell + " --width 128 --height 128 --spp 4 -q -o " + dir.file("a.exr"))
            .code == 0);
    const std::string ref = foton::test::shared_path("refs/cornell_diffuse_path_512spp.exr");
    const Run c = run("compare " + dir.file("a.exr") + " " + ref + " --exclude-above 2 --diff " +
                      dir.file("d.png"));
    CHECK(c.code == 0);
    CHECK_THAT(c.output, Catch::Contains("reference downsampled 4x to 128x128"));
    CHECK_THAT(c.output, Catch::Contains("rmse"));
    CHECK_THAT(c.output, Catch::Contains("relative_mse"));
    CHECK_THAT(c.output, Catch::Contains("mae"));
    CHECK_THAT(c.output, Catch::Contains("ssim 0."));
    CHECK(std::filesystem::file_size(dir.file("d.png")) > 0);
    // The light (luminance 15) is about 1 % of the pixels; excluding it drops them.
    const auto pixels = [](const std::string& out) {
        const auto at = out.find("pixels ");
        return std::stoul(out.substr(at + 7));
    };
    const Run all = run("compare " + dir.file("a.exr") + " " + ref);
    CHECK(pixels(c.output) < pixels(all.output));
    CHECK(pixels(all.output) == 128u * 128u);
    // A mask PNG of the wrong size is bad input; an image against itself has zero error.
    CHECK(run("compare " + dir.file("a.exr") + " " + ref + " --mask " + dir.file("d.png")).code ==
          0);
    const Run self = run("compare " + dir.file("a.exr") + " " + dir.file("a.exr"));
    CHECK_THAT(self.output, Catch::Contains("rmse 0\n"));
    CHECK(run("compare " + dir.file("a.exr") + " " + ref + " --mask " +
              foton::test::source_path("scenes/previews/bunny.png"))
              .code == 2);
    // --lowpass: one line per filter width; width 1 is the RMSE itself, wider ones less.
    const Run lp = run("compare " + dir.file("a.exr") + " " + ref + " --lowpass 1,4");
    CHECK(lp.code == 0);
    const auto value = [](const std::string& out, const std::string& key) {
        const auto at = out.find(key);
        REQUIRE(at != std::string::npos);
        return std::stod(out.substr(at + key.size()));
    };
    CHECK(value(lp.output, "lowpass_rmse 1 ") == Approx(value(lp.output, "rmse ")).epsilon(1e-5));
    CHECK(value(lp.output, "lowpass_rmse 4 ") < 0.5 * value(lp.output, "rmse "));
    CHECK(run("compare " + dir.file("a.exr") + " " + ref + " --lowpass 0").code != 0);
}

TEST_CASE("foton render --sampler is the renderer's sampler setting", "[cli]") {
    foton::test::TempDir dir;
    const std::string cornell = foton::test::source_path("scenes/cornell-diffuse.xml");
    const std::string common = " --width 16 --height 16 --spp 4 --integrator path -q -o ";
    REQUIRE(run("render " + cornell + " --sampler zsobol" + common + dir.file("a.exr")).code == 0);
    REQUIRE(run("render " + cornell + " --set sampler=zsobol" + common + dir.file("b.exr")).code ==
            0);
    REQUIRE(run("render " + cornell + common + dir.file("c.exr")).code == 0);
    const foton::Film a = foton::read_exr(dir.file("a.exr"));
    CHECK(foton::compare_images(a, foton::read_exr(dir.file("b.exr"))).max_abs == 0.0);
    CHECK(foton::compare_images(a, foton::read_exr(dir.file("c.exr"))).max_abs > 0.0);
    const Run bad = run("render " + cornell + " --sampler blue" + common + dir.file("d.exr"));
    CHECK(bad.code == 2);
    CHECK_THAT(bad.output, Catch::Contains("--sampler"));
    CHECK_THAT(bad.output, Catch::Contains("zsobol"));
}

TEST_CASE("foton render --set overrides renderer attributes and checks them", "[cli]") {
    foton::test::TempDir dir;
    const std::string cornell = foton::test::source_path("scenes/cornell-caustics.xml");
    const Run ok = run("render " + cornell +
                       " --width 16 --height 16 --spp 1 --integrator photon --set gather_rays=2"
                       " --set global_photons=20000 --set caustic_filter=cone --stats -q -o " +
                       dir.file("p.exr"));
    CHECK(ok.code == 0);
    CHECK_THAT(ok.output, Catch::Contains("final-gather"));  // the photon stages ran
    const Run bad = run("render " + cornell + " --set k=abc -o " + dir.file("b.exr"));
    CHECK(bad.code == 2);
    CHECK_THAT(bad.output, Catch::Contains("--set: setting 'k' is not a number"));
    // Settings are checked by name whatever the scene format: a misspelt key is an error.
    const Run typo = run("render " + cornell + " --set gather_ray=4 -o " + dir.file("b.exr"));
    CHECK(typo.code == 2);
    CHECK_THAT(typo.output, Catch::Contains("unknown setting 'gather_ray' (did you mean "
                                            "'gather_rays'?)"));
    CHECK(run("render " + cornell + " --set nonsense -o " + dir.file("b.exr")).code == 2);
    CHECK(run("render " + cornell + " --set colour=red -o " + dir.file("b.exr")).code == 2);
    CHECK_FALSE(std::filesystem::exists(dir.file("b.exr")));
}

TEST_CASE("foton render records what ran: samples, threads, machine", "[cli]") {
    foton::test::TempDir dir;
    auto attribute = [](const std::string& exr, const std::string& key) {
        for (const auto& [k, v] : foton::read_exr_attributes(exr))
            if (k == key) return v;
        return std::string("(missing)");
    };
    auto json = [](const std::string& path) {
        std::ifstream in(path);
        return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    };
    const std::string caustics = foton::test::source_path("scenes/cornell-caustics.xml");
    // SPPM: --spp is the number of passes, one sample per pixel each.
    const Run sppm = run("render " + caustics + " --width 16 --height 12 --integrator sppm" +
                         " --spp 4 --threads 64 -q --stats-json " + dir.file("s.json") + " -o " +
                         dir.file("s.exr"));
    REQUIRE(sppm.code == 0);
    CHECK(attribute(dir.file("s.exr"), "foton:samples") == "4");
    // pbrt-v4's standard attributes, the command line and the settings as used.
    CHECK(attribute(dir.file("s.exr"), "samplesPerPixel") == "4");
    CHECK(std::stod(attribute(dir.file("s.exr"), "renderTimeSeconds")) > 0.0);
    CHECK_THAT(attribute(dir.file("s.exr"), "foton:commandLine"),
               Catch::Contains("--integrator sppm --spp 4"));
    CHECK_THAT(attribute(dir.file("s.exr"), "foton:settings"), Catch::Contains("type=sppm"));
    CHECK(attribute(dir.file("s.exr"), "foton:gitCommit").size() >= 7);
    for (const char* m : {"worldToCamera", "worldToNDC"}) {
        // 16 numbers, the last column's homogeneous entries included.
        std::stringstream ss(attribute(dir.file("s.exr"), m));
        int n = 0;
        for (double v; ss >> v;) ++n;
        CHECK(n == 16);
    }
    const nlohmann::json js = nlohmann::json::parse(json(dir.file("s.json")));
    // More threads than the machine has really run (oversubscribed), and the record says so
    // beside the machine's own count.
    CHECK(js["threads_requested"] == 64);
    CHECK(js["threads"] == 64);
    CHECK(js.contains("hardware_threads"));
    for (const char* field :
         {"schema_version", "cpu", "simd", "simd_width", "seed", "photons_global", "graph"})
        CHECK(js.contains(field));
    CHECK(js["spp_mean"] == 4);
    CHECK(js["integrator"] == "sppm");
    CHECK(js["width"] == 16);
    // Adaptive sampling: the mean of what the pixels averaged, not the pilot.
    const Run adaptive = run("render " + caustics + " --width 16 --height 12 --integrator path" +
                             " --spp 2 --adaptive 0.05 --adaptive-max 16 -q --stats-json " +
                             dir.file("a.json") + " -o " + dir.file("a.exr"));
    REQUIRE(adaptive.code == 0);
    const double mean = std::stod(attribute(dir.file("a.exr"), "foton:samples"));
    CHECK(mean > 2.0);
    CHECK(mean <= 16.0);
    CHECK(attribute(dir.file("a.exr"), "worldToNDC") != "(missing)");
    CHECK_THAT(json(dir.file("a.json")), Catch::Contains("\"git_commit\""));
    // The flags that are settings are recorded as the run used them.
    CHECK(run("render " + caustics + " --width 8 --height 8 --integrator path --mis balance" +
              " --max-depth 3 -q -o " + dir.file("m.exr"))
              .code == 0);
    const std::string settings = attribute(dir.file("m.exr"), "foton:settings");
    CHECK_THAT(settings, Catch::Contains("mis=balance"));
    CHECK_THAT(settings, Catch::Contains("max_depth=3"));
    // Snapshots need a timed render; without one they are an error, not ignored.
    const Run snap =
        run("render " + caustics + " --width 8 --height 8 --snapshots 1 -o " + dir.file("n.exr"));
    CHECK(snap.code == 2);
    CHECK_THAT(snap.output, Catch::Contains("--snapshots: needs --time"));
    CHECK_FALSE(std::filesystem::exists(dir.file("n.exr")));
}

TEST_CASE("foton render --reference: a convergence curve whose last error is foton compare's",
          "[cli]") {
    foton::test::TempDir dir;
    const std::string scene = foton::test::source_path("scenes/cornell-diffuse.xml");
    const std::string size = " --width 32 --height 32 -q";
    REQUIRE(run("render " + scene + size + " --spp 32 --seed 9 -o " + dir.file("ref.exr")).code ==
            0);
    for (const char* method : {"path", "light", "sppm", "photon"}) {
        INFO(method);
        const Run r = run("render " + scene + size + " --integrator " + method +
                          " --passes 4 --reference " + dir.file("ref.exr") +
                          " --exclude-above 2 --set global_photons=5000 --set "
                          "caustic_photons=0 --set gather_rays=8 -o " +
                          dir.file("a.exr") + " --stats-json " + dir.file("a.json"));
        REQUIRE(r.code == 0);
        std::ifstream csv(dir.file("a.convergence.csv"));
        std::string header, line;
        std::getline(csv, header);
        CHECK(header ==
              "passes,seconds,cpu_seconds,spp,rmse,relative_mse,mae,bias_r,bias_g,"
              "bias_b,ssim");
        std::vector<std::vector<double>> rows;
        while (std::getline(csv, line)) {
            std::vector<double> v;
            std::stringstream ss(line);
            for (std::string cell; std::getline(ss, cell, ',');) v.push_back(std::stod(cell));
            REQUIRE(v.size() == 11);
            rows.push_back(v);
        }
        REQUIRE(rows.size() == 4);
        for (std::size_t i = 0; i < rows.size(); ++i) {
            CHECK(rows[i][0] == double(i + 1));
            if (i > 0) {
                CHECK(rows[i][1] > rows[i - 1][1]);  // wall time grows
                CHECK(rows[i][3] > rows[i - 1][3]);  // so do the samples
            }
        }
        // The last row is the written image's error, as foton compare measures it.
        const Run c =
            run("compare " + dir.file("a.exr") + " " + dir.file("ref.exr") + " --exclude-above 2");
        REQUIRE(c.code == 0);
        const std::size_t at = c.output.find("rmse ");
        REQUIRE(at != std::string::npos);
        CHECK(rows.back()[4] == Approx(std::stod(c.output.substr(at + 5))).epsilon(1e-5));
        const std::size_t s_at = c.output.find("ssim ");
        REQUIRE(s_at != std::string::npos);
        CHECK(rows.back()[10] == Approx(std::stod(c.output.substr(s_at + 5))).epsilon(1e-5));
        CHECK(rows.back()[10] > 0.0);
        CHECK(rows.back()[10] < 1.0);
        std::ifstream js(dir.file("a.json"));
        const std::string json((std::istreambuf_iterator<char>(js)),
                               std::istreambuf_iterator<char>());
        const nlohmann::json j = nlohmann::json::parse(json);
        REQUIRE(j["convergence"].is_array());
        bool fourth = false;
        for (const nlohmann::json& point : j["convergence"]) fourth |= point["passes"] == 4;
        CHECK(fourth);
    }
    // Bad use: a reference of another size, --exclude-above alone; no image either way.
    const Run wrong = run("render " + scene + " --width 24 --height 32 -q --reference " +
                          dir.file("ref.exr") + " -o " + dir.file("w.exr"));
    CHECK(wrong.code == 2);
    CHECK_THAT(wrong.output, Catch::Contains("ref.exr: image is 32x32, the render is 24x32"));
    CHECK_FALSE(std::filesystem::exists(dir.file("w.exr")));
    const Run alone = run("render " + scene + size + " --exclude-above 2 -o " + dir.file("w.exr"));
    CHECK(alone.code == 2);
    CHECK_THAT(alone.output, Catch::Contains("--exclude-above: needs --reference"));
}

TEST_CASE("foton render --crop and --pixel-bounds", "[cli][crop]") {
    foton::test::TempDir dir;
    const std::string scene = foton::test::source_path("scenes/cornell-diffuse.xml");
    const std::string common = " --width 40 --height 20 --spp 1 -q --seed 3";
    REQUIRE(run("render " + scene + common + " -o " + dir.file("full.exr")).code == 0);
    // Fractions as pbrt's --cropwindow: [ceil(0.25 * 40), ceil(0.75 * 40)) = [10, 30).
    REQUIRE(run("render " + scene + common + " --crop 0.25,0.75,0.1,0.6 -o " + dir.file("c.exr"))
                .code == 0);
    REQUIRE(run("render " + scene + common + " --pixel-bounds 10,30,2,12 -o " + dir.file("p.exr"))
                .code == 0);
    const foton::Film full = foton::read_exr(dir.file("full.exr"));
    for (const char* f : {"c.exr", "p.exr"}) {
        const foton::Film c = foton::read_exr(dir.file(f));
        REQUIRE(c.width == 20);
        REQUIRE(c.height == 10);
        int differing = 0;
        for (int y = 0; y < 10; ++y)
            for (int x = 0; x < 20; ++x) {
                const foton::RGB& p = full.at(10 + x, 2 + y);
                const foton::RGB& q = c.at(x, y);
                differing += p.r != q.r || p.g != q.g || p.b != q.b;
            }
        CHECK(differing == 0);
    }
    // A reference of the whole image serves a crop's convergence curve.
    CHECK(run("render " + scene + common + " --pixel-bounds 10,30,2,12 --passes 2 --reference " +
              dir.file("full.exr") + " -o " + dir.file("r.exr"))
              .code == 0);
    for (const char* bad : {"--crop 0.5,0.5,0,1", "--crop 0,1.5,0,1", "--pixel-bounds 0,41,0,20",
                            "--pixel-bounds 1,2,3", "--crop 0,1,0,1 --pixel-bounds 0,1,0,1"}) {
        INFO(bad);
        const Run r = run("render " + scene + common + " " + bad + " -o " + dir.file("bad.exr"));
        CHECK(r.code == 2);
        CHECK_FALSE(std::filesystem::exists(dir.file("bad.exr")));
    }
}

TEST_CASE("foton render and info read pbrt-v4 files, bad ones exit 2 with no image",
          "[cli][pbrt]") {
    foton::test::TempDir dir;
    const std::string good = dir.file("ok.pbrt");
    std::ofstream(good) << "LookAt 0 0 -3  0 0 0  0 1 0\nCamera \"perspective\"\n"
                           "PixelFilter \"mitchell\" \"float foo\" 1\nWorldBegin\n"
                           "LightSource \"point\" \"rgb I\" [5 5 5] \"point3 from\" [0 2 -2]\n"
                           "Shape \"sphere\"\n";
    const Run r =
        run("render " + good + " --width 16 --height 16 --spp 1 -o " + dir.file("ok.exr"));
    CHECK(r.code == 0);
    CHECK_THAT(r.output, Catch::Contains("warning: " + good +
                                         ":3: unsupported parameter 'float foo' of PixelFilter"));
    CHECK(std::filesystem::exists(dir.file("ok.exr")));
    const Run i = run("info " + good);
    CHECK(i.code == 0);
    CHECK_THAT(i.output, Catch::Contains("imported   Camera perspective;"));
    CHECK_THAT(i.output, Catch::Contains("ignored    " + good + ":3:"));
    CHECK_THAT(i.output, Catch::Contains("filter mitchell, radius 2 x 2, b 0.333333"));
    const std::string bad = dir.file("bad.pbrt");
    std::ofstream(bad) << "WorldBegin\nShape \"sphere\" \"float radius\" [ -1 ]\n";
    const Run b = run("render " + bad + " -o " + dir.file("bad.exr"));
    CHECK(b.code == 2);
    CHECK_THAT(b.output, Catch::Contains(bad + ":2: sphere radius must be positive"));
    CHECK(!std::filesystem::exists(dir.file("bad.exr")));
    CHECK(!std::filesystem::exists(dir.file("bad.png")));
}

TEST_CASE("bad mesh files, textures and environment maps exit 2 with no image",
          "[cli][bad-input]") {
    foton::test::TempDir dir;
    auto scene_with = [&](const std::string& lights, const std::string& object) {
        std::ofstream(dir.file("s.xml"))
            << "<scene>\n<lights>" << lights << "</lights>\n<objects>\n"
            << object
            << "\n</objects>\n<film width=\"8\" height=\"8\"/>\n"
               "<camera><eye x=\"0\" y=\"0\" z=\"-5\"/><target x=\"0\" y=\"0\" z=\"0\"/></camera>\n"
               "</scene>\n";
    };
    auto expect = [&](const std::string& what) {
        const Run r = run("render " + dir.file("s.xml") + " -q -o " + dir.file("out.exr"));
        CHECK(r.code == 2);
        CHECK_THAT(r.output, Catch::Contains(what));
        CHECK_FALSE(std::filesystem::exists(dir.file("out.exr")));
        CHECK_FALSE(std::filesystem::exists(dir.file("out.png")));
    };
    const std::string sphere = R"(<sphere radius="1"><center x="0" y="0" z="0"/>)";
    std::ofstream(dir.file("bad.gltf")) << "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [";
    scene_with("", R"(<triangle_mesh src="bad.gltf"/>)");
    expect("s.xml:4: " + dir.file("bad.gltf") + ": malformed glTF");
    std::ofstream(dir.file("bad.ply")) << "ply\nformat ascii 1.0\nelement vertex 3\nend_header\n";
    scene_with("", R"(<triangle_mesh src="bad.ply"/>)");
    expect("bad.ply:");
    std::ofstream(dir.file("not-an-image.png")) << "this is text";
    scene_with("", sphere + R"(<material type="lambert"><texture src="not-an-image.png"/>
      </material></sphere>)");
    expect("s.xml:4: texture 'not-an-image.png'");
    scene_with(R"(<environment src="not-an-image.png"/>)",
               sphere + "<material type=\"lambert\"/></sphere>");
    expect("s.xml:2: environment map 'not-an-image.png'");
    foton::Film wide(6, 4);
    foton::write_exr(dir.file("wide.exr"), wide);
    scene_with(R"(<environment src="wide.exr" mapping="equalarea"/>)",
               sphere + "<material type=\"lambert\"/></sphere>");
    expect("must be square, not 6x4");
    // Issue 36's three: a broken .ply.gz (plain text where gzip data belongs) through pbrt's
    // plymesh, a truncated PFM environment map, a glTF texture index out of range.
    std::ofstream(dir.file("broken.ply.gz")) << "ply\nformat ascii 1.0\nelement vertex 3\n";
    std::ofstream(dir.file("b.pbrt"))
        << "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nFilm \"rgb\" \"integer "
           "xresolution\" [8] \"integer yresolution\" [8]\nWorldBegin\n"
           "Shape \"plymesh\" \"string filename\" \"broken.ply.gz\"\n";
    const Run ply = run("render " + dir.file("b.pbrt") + " -q -o " + dir.file("out.exr"));
    CHECK(ply.code == 2);
    CHECK_THAT(ply.output, Catch::Contains("b.pbrt:5:") && Catch::Contains("corrupt gzip data"));
    CHECK_FALSE(std::filesystem::exists(dir.file("out.exr")));
    std::ofstream(dir.file("cut.pfm"), std::ios::binary) << "PF\n4 2\n-1\n"
                                                         << std::string(40, '\0');
    scene_with(R"(<environment src="cut.pfm"/>)", sphere + "<material type=\"lambert\"/></sphere>");
    expect("PFM data is short");
    std::ofstream(dir.file("quad.gltf"))
        << R"({"asset": {"version": "2.0"}, "meshes": [{"primitives": [{"attributes":
           {"POSITION": 0}, "material": 0}]}], "nodes": [{"mesh": 0}],
           "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 5}}}],
           "accessors": [{"componentType": 5126, "count": 3, "type": "VEC3", "bufferView": 0,
           "min": [0, 0, 0], "max": [1, 1, 0]}],
           "bufferViews": [{"buffer": 0, "byteLength": 36}],
           "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]})";
    scene_with("", R"(<triangle_mesh src="quad.gltf"/>)");
    expect("texture 5 does not exist");
}

TEST_CASE("foton render --preview writes the tone-mapped image as PNG, JPEG or BMP", "[cli]") {
    foton::test::TempDir dir;
    const std::string scene = foton::test::source_path("scenes/cornell-box.xml");
    std::vector<unsigned char> images[3];
    const char* formats[] = {"png", "jpg", "bmp"};
    for (int k = 0; k < 3; ++k) {
        const std::string out = dir.file(std::string("c-") + formats[k] + ".exr");
        const Run r = run("render " + scene + " --width 24 --height 16 --spp 1 -o " + out +
                          " --preview " + formats[k]);
        REQUIRE(r.code == 0);
        const std::string preview = dir.file(std::string("c-") + formats[k] + "." + formats[k]);
        CHECK_THAT(r.output, Catch::Contains("wrote " + preview));
        int w = 0, h = 0, c = 0;
        unsigned char* px = stbi_load(preview.c_str(), &w, &h, &c, 3);
        REQUIRE(px);
        CHECK(w == 24);
        CHECK(h == 16);
        images[k].assign(px, px + 24 * 16 * 3);
        stbi_image_free(px);
    }
    // BMP is lossless: the PNG's bytes; JPEG is close to them.
    CHECK(images[2] == images[0]);
    double diff = 0.0;
    for (std::size_t i = 0; i < images[0].size(); ++i)
        diff += std::abs(int(images[1][i]) - int(images[0][i]));
    CHECK(diff / double(images[0].size()) < 6.0);
    CHECK(run("render " + scene + " --width 8 --height 8 --spp 1 -q -o " + dir.file("x.exr") +
              " --preview tiff")
              .code == 2);
}

TEST_CASE("statistics JSON escapes every string and survives invalid UTF-8", "[cli][fast]") {
    foton::RenderStats st;
    st.camera_rays = 7;
    const std::string text =
        st.json({{"scene", "a \"quoted\" \\ path\n"}, {"bytes", std::string("bad \xff utf-8")}});
    const nlohmann::json j = nlohmann::json::parse(text);
    CHECK(j["scene"] == "a \"quoted\" \\ path\n");
    CHECK(j["camera_rays"] == 7);
    CHECK(j["schema_version"] == 2);
    CHECK(j["bytes"].get<std::string>().rfind("bad ", 0) == 0);
}

TEST_CASE("foton serve and render refuse ports, hosts and snapshot times they cannot honour",
          "[cli][serve][fast]") {
    const Run port = run("serve --port 70000");
    CHECK(port.code == 2);
    CHECK_THAT(port.output, Catch::Contains("not a TCP port"));
    const Run remote = run("serve --host 0.0.0.0 --port 0");
    CHECK(remote.code == 2);
    CHECK_THAT(remote.output, Catch::Contains("--allow-remote"));
    foton::test::TempDir dir;
    const std::string scene = foton::test::source_path("scenes/cornell-box.xml");
    for (const char* t : {"-1", "nan", "inf", "0"}) {
        INFO(t);
        const Run r = run("render " + scene + " --width 8 --height 8 -q --time 0.1 --snapshots " +
                          t + " -o " + dir.file("s.exr"));
        CHECK(r.code == 2);
        CHECK_THAT(r.output, Catch::Contains("--snapshots"));
        CHECK_FALSE(std::filesystem::exists(dir.file("s.exr")));
    }
    for (const char* t : {"nan", "inf", "-1"}) {
        INFO(t);
        const Run r = run("render " + scene + " --width 8 --height 8 -q --time " + std::string(t) +
                          " -o " + dir.file("t.exr"));
        CHECK(r.code == 2);
        CHECK_THAT(r.output, Catch::Contains("--time"));
    }
}

TEST_CASE("foton compare counts NaN and infinite pixels and says so in its exit code",
          "[cli][compare][fast]") {
    foton::test::TempDir dir;
    foton::Film a(4, 2), b(4, 2);
    for (auto& p : a.pixels) p = foton::RGB{0.5f};
    b = a;
    foton::write_exr(dir.file("a.exr"), a);
    foton::write_exr(dir.file("b.exr"), b);
    const Run same = run("compare " + dir.file("a.exr") + " " + dir.file("b.exr"));
    CHECK(same.code == 0);
    CHECK_THAT(same.output, Catch::Contains("nonfinite_a 0"));
    a.pixels[3].g = std::numeric_limits<float>::quiet_NaN();
    a.pixels[5].b = std::numeric_limits<float>::infinity();
    foton::write_exr(dir.file("a.exr"), a);
    const Run bad = run("compare " + dir.file("a.exr") + " " + dir.file("b.exr"));
    CHECK(bad.code == 3);
    CHECK_THAT(bad.output, Catch::Contains("nonfinite_a 2"));
    CHECK_THAT(bad.output, Catch::Contains("nonfinite_b 0"));
    CHECK_THAT(bad.output, Catch::Contains("max_abs nan"));
    const foton::ImageError e = foton::compare_images(a, b);
    CHECK(e.nonfinite_a == 2);
    CHECK(std::isnan(e.max_abs));
}

TEST_CASE("outputs are distinct from each other and from the inputs", "[cli][bad-input][fast]") {
    foton::test::TempDir dir;
    const std::string scene = foton::test::source_path("scenes/cornell-box.xml");
    const std::string common = "render " + scene + " --width 8 --height 8 -q ";
    const std::string a = dir.file("a.exr");
    Run r = run(common + "-o " + a + " --stats-json " + a);
    CHECK(r.code == 2);
    CHECK_THAT(r.output, Catch::Contains("also written by -o"));
    CHECK_FALSE(std::filesystem::exists(a));
    // A reference to compare against, then a render told to write over it.
    REQUIRE(run(common + "-o " + a).code == 0);
    const auto before = std::filesystem::last_write_time(a);
    r = run(common + "--time 0.05 --reference " + a + " -o " + a);
    CHECK(r.code == 2);
    CHECK_THAT(r.output, Catch::Contains("--reference image itself"));
    CHECK(std::filesystem::last_write_time(a) == before);
    r = run(common + "--time 0.05 --snapshots 0.01 -o " + a + " --stats-json " +
            dir.file("a-0.01s.exr"));
    CHECK(r.code == 2);
    CHECK_THAT(r.output, Catch::Contains("also written by"));
    // compare's difference image over one of its inputs.
    r = run("compare " + a + " " + a + " --diff " + a);
    CHECK(r.code == 2);
    CHECK_THAT(r.output, Catch::Contains("first image itself"));
    CHECK(std::filesystem::last_write_time(a) == before);
}
