// The EXR header's camera matrices as pbrt-v4 writes them (issue 34): foton once wrote their
// transpose, with NDC's y flipped. A render of the pbrt-v4 Cornell box (scenes/pbrt/cornell)
// must carry the worldToCamera and worldToNDC that pbrt-v4 computes for that camera, checked
// against values computed here from pbrt-v4's definitions and against the header of pbrt-v4's
// own render of the same scene (../shared/refs).
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "engine/app/render_job.h"
#include "engine/film/image_io.h"
#include "engine/scene/xml_loader.h"
#include "test_util.h"

using namespace foton;

namespace {

std::vector<double> matrix(const ImageAttributes& attrs, const std::string& name) {
    for (const auto& [k, v] : attrs)
        if (k == name) {
            std::istringstream in(v);
            std::vector<double> m;
            for (double x; in >> x;) m.push_back(x);
            return m;
        }
    return {};
}

void check_close(const std::vector<double>& got, const std::vector<double>& want) {
    REQUIRE(got.size() == 16);
    REQUIRE(want.size() == 16);
    for (std::size_t i = 0; i < 16; ++i) {
        INFO("entry " << i / 4 << "," << i % 4);
        CHECK(got[i] == Approx(want[i]).margin(1e-3).epsilon(1e-5));
    }
}

// pbrt-v4's matrices for camera_common.pbrt: Scale -1 1 1, LookAt (278, 277.5, -800) ->
// (278, 277.5, 0) up +y, fov 39.3077 on a square image. cameraFromWorld is the CTM at Camera;
// NDCFromWorld = Translate(.5,.5,.5) Scale(.5,.5,.5) Perspective(fov, 1e-2, 1000) cameraFromWorld.
std::vector<double> pbrt_world_to_camera() {
    return {-1, 0, 0, 278, 0, 1, 0, -277.5, 0, 0, 1, 800, 0, 0, 0, 1};
}
std::vector<double> pbrt_world_to_ndc() {
    const double kPiD = 3.14159265358979323846;
    const double inv_tan = 1.0 / std::tan(39.3077 * kPiD / 180.0 / 2.0);
    const double n = 1e-2, f = 1000.0, zz = f / (f - n);
    const double p[4][4] = {{0.5 * inv_tan, 0, 0.5, 0},
                            {0, 0.5 * inv_tan, 0.5, 0},
                            {0, 0, 0.5 * zz + 0.5, -0.5 * zz * n},
                            {0, 0, 1, 0}};
    const std::vector<double> c = pbrt_world_to_camera();
    std::vector<double> m(16, 0.0);
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            for (int k = 0; k < 4; ++k)
                m[std::size_t(i * 4 + j)] += p[i][k] * c[std::size_t(k * 4 + j)];
    return m;
}

}  // namespace

TEST_CASE("EXR metadata: worldToCamera and worldToNDC of the pbrt-v4 Cornell box are pbrt-v4's",
          "[exr][pbrt][fast]") {
    const Scene scene = load_scene(test::source_path("scenes/pbrt/cornell/path_diffuse.pbrt"));
    test::TempDir dir;
    const std::string path = dir.file("m.exr");
    write_exr(path, Film(4, 4), {}, app::job_exr_info(scene, 1.0, 1.0));
    const ImageAttributes ours = read_exr_attributes(path);
    check_close(matrix(ours, "worldToCamera"), pbrt_world_to_camera());
    check_close(matrix(ours, "worldToNDC"), pbrt_world_to_ndc());

    // And pbrt-v4's own render of this camera, where ../shared is beside the repository.
    const std::string ref = test::shared_path("refs/cornell_diffuse_path_512spp.exr");
    if (!std::filesystem::exists(ref)) {
        WARN("no " << ref << ": compared with the computed matrices only");
        return;
    }
    const ImageAttributes pbrt = read_exr_attributes(ref);
    check_close(matrix(ours, "worldToCamera"), matrix(pbrt, "worldToCamera"));
    check_close(matrix(ours, "worldToNDC"), matrix(pbrt, "worldToNDC"));
}

TEST_CASE("EXR metadata: MSE against --reference, and samplesPerPixel only when exact",
          "[exr][cli]") {
    test::TempDir dir;
    auto attribute = [](const std::string& exr, const std::string& key) {
        for (const auto& [k, v] : read_exr_attributes(exr))
            if (k == key) return v;
        return std::string("(missing)");
    };
    const std::string diffuse = test::source_path("scenes/cornell-diffuse.xml");
    // A reference at the render's own size: the image against itself at another seed.
    const test::FotonRun ref = test::run_foton("render " + diffuse + " --width 32 --height 32 " +
                                               "--spp 4 --seed 9 -q -o " + dir.file("ref.exr"));
    REQUIRE(ref.code == 0);
    const test::FotonRun r =
        test::run_foton("render " + diffuse + " --width 32 --height 32 --passes 2 --reference " +
                        dir.file("ref.exr") + " -q -o " + dir.file("a.exr") + " --convergence " +
                        dir.file("a.csv"));
    REQUIRE(r.code == 0);
    // pbrt-v4's MSE: the last CSV row's rmse, squared.
    std::ifstream csv(dir.file("a.csv"));
    std::string line, last;
    while (std::getline(csv, line))
        if (!line.empty()) last = line;
    std::stringstream row(last);
    std::vector<double> cols;
    for (std::string cell; std::getline(row, cell, ',');) cols.push_back(std::stod(cell));
    REQUIRE(cols.size() >= 5);
    const double rmse = cols[4];
    CHECK(std::stod(attribute(dir.file("a.exr"), "MSE")) == Approx(rmse * rmse).epsilon(1e-4));
    CHECK(attribute(dir.file("a.exr"), "samplesPerPixel") == "2");
    // Adaptive sampling: a mean that is not a whole number is not rounded into samplesPerPixel.
    const test::FotonRun ad = test::run_foton("render " + diffuse +
                                              " --width 32 --height 32 --spp 4 --adaptive 0.05 "
                                              "--adaptive-max 64 -q -o " +
                                              dir.file("ad.exr"));
    REQUIRE(ad.code == 0);
    const double mean = std::stod(attribute(dir.file("ad.exr"), "foton:samples"));
    if (mean != std::floor(mean))
        CHECK(attribute(dir.file("ad.exr"), "samplesPerPixel") == "(missing)");
    else
        CHECK(attribute(dir.file("ad.exr"), "samplesPerPixel") == std::to_string(int(mean)));
    CHECK(attribute(dir.file("a.exr"), "MSE") != "(missing)");
    CHECK(attribute(dir.file("ad.exr"), "MSE") == "(missing)");
}
