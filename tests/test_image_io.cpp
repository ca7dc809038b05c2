#include <catch2/catch.hpp>
#include <filesystem>

#include "engine/core/error.h"
#include "engine/film/image_io.h"
#include "engine/film/metrics.h"
#include "test_util.h"

using namespace foton;

TEST_CASE("EXR round trip keeps float values", "[image][fast]") {
    test::TempDir dir;
    Film f(7, 5);
    for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 7; ++x) f.at(x, y) = RGB(float(x) * 0.1f, float(y) * 10.f, 1e-3f);
    write_exr(dir.file("a.exr"), f, {{"foton:test", "yes"}});
    const Film g = read_exr(dir.file("a.exr"));
    REQUIRE(g.width == 7);
    REQUIRE(g.height == 5);
    CHECK(compare_images(f, g).max_abs == 0.0);
    // Only the final file remains: the temporary was renamed.
    int files = 0;
    for ([[maybe_unused]] auto& e : std::filesystem::directory_iterator(dir.path())) ++files;
    CHECK(files == 1);
}

TEST_CASE("writing into a missing directory fails cleanly", "[image][bad-input][fast]") {
    Film f(2, 2);
    CHECK_THROWS_AS(write_exr("/nonexistent-dir/x.exr", f), InputError);
    CHECK_THROWS_AS(read_exr("/nonexistent-dir/x.exr"), InputError);
}

TEST_CASE("image metrics", "[image][fast]") {
    Film a(2, 1), b(2, 1);
    a.at(0, 0) = RGB(1.f);
    b.at(0, 0) = RGB(0.f);
    const ImageError e = compare_images(a, b);
    CHECK(e.rmse == Approx(std::sqrt(0.5)));
    CHECK(e.mae == Approx(0.5));
    CHECK(e.max_abs == 1.0);
    const std::vector<uint8_t> mask = {0, 1};
    CHECK(compare_images(a, b, &mask).rmse == 0.0);
    CHECK(compare_images(a, a).rmse == 0.0);
}

TEST_CASE("the exclusion mask grows by its margin, clipped at the image's edge", "[image][fast]") {
    // A 5 x 4 image with one excluded pixel at (1, 1) and one at (4, 3).
    std::vector<uint8_t> m(20, 1);
    m[1 * 5 + 1] = 0;
    m[3 * 5 + 4] = 0;
    const std::vector<uint8_t> g = grow_exclusion(m, 5, 4, 1);
    const char* expect =
        "000.."
        "000.."
        "00000"
        "...00";
    for (int i = 0; i < 20; ++i) {
        INFO("pixel " << i);
        CHECK(g[std::size_t(i)] == (expect[i] == '.' ? 1 : 0));
    }
    CHECK(grow_exclusion(m, 5, 4, 0) == m);
}
