// Portable float maps (engine/film/pfm_reader.h): both byte orders, colour and grey, rows
// bottom-up, the scale applied; as a texture (an environment map's image); and every bad
// header or short file as bad input at its line.
#include <bit>
#include <catch2/catch.hpp>
#include <cstring>
#include <fstream>

#include "engine/core/error.h"
#include "engine/film/pfm_reader.h"
#include "engine/scene/texture.h"
#include "test_util.h"

using namespace foton;

namespace {

// A PFM of `values` (rows top-down as given, written bottom-up), in the byte order `little`.
std::string pfm(const char* magic, int w, int h, float scale, bool little,
                const std::vector<float>& values) {
    std::string s = std::string(magic) + "\n" + std::to_string(w) + " " + std::to_string(h) + "\n" +
                    std::to_string(little ? -scale : scale) + "\n";
    const int c = std::string(magic) == "PF" ? 3 : 1;
    for (int y = h - 1; y >= 0; --y)
        for (int i = 0; i < w * c; ++i) {
            uint32_t u = std::bit_cast<uint32_t>(values[std::size_t(y * w * c + i)]);
            if (little != (std::endian::native == std::endian::little)) u = __builtin_bswap32(u);
            char b[4];
            std::memcpy(b, &u, 4);
            s.append(b, 4);
        }
    return s;
}

std::string error_of(const std::string& bytes) {
    try {
        parse_pfm(bytes, "m.pfm");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("PFM: byte orders, colour and grey, bottom-up rows, the scale", "[image][fast]") {
    const std::vector<float> rgb = {1,  2,  3,  4,  5,  6,  7,  8,  9,  // top row
                                    10, 11, 12, 13, 14, 15, 16, 17, 18};
    for (const bool little : {true, false}) {
        const Film f = parse_pfm(pfm("PF", 3, 2, 2.f, little, rgb), "m.pfm");
        REQUIRE(f.width == 3);
        REQUIRE(f.height == 2);
        CHECK(f.pixels[0].r == 2.f);  // the top-left pixel, times the scale
        CHECK(f.pixels[2].b == 18.f);
        CHECK(f.pixels[5].b == 36.f);  // the bottom-right
    }
    const Film g = parse_pfm(pfm("Pf", 2, 2, 1.f, true, {0.5f, 1.5f, 2.5f, 3.5f}), "g.pfm");
    CHECK(g.pixels[1].r == 1.5f);
    CHECK(g.pixels[1].b == 1.5f);
    CHECK(g.pixels[3].g == 3.5f);
    // As a texture (environment maps load through it).
    test::TempDir dir;
    std::ofstream(dir.file("env.pfm"), std::ios::binary) << pfm("PF", 3, 2, 1.f, true, rgb);
    const TextureImage img = load_texture_image(dir.file("env.pfm"), true);
    CHECK(img.width == 3);
    CHECK(img.texels[4].g == 14.f);
}

TEST_CASE("PFM: bad headers and short data are bad input at their line",
          "[image][bad-input][fast]") {
    CHECK_THAT(error_of("P6\n3 2\n255\n"), Catch::Contains("m.pfm:1: not a PFM image"));
    CHECK_THAT(error_of("PF\nthree 2\n-1\n"), Catch::Contains("m.pfm:2: PFM width 'three'"));
    CHECK_THAT(error_of("PF\n3 -2\n-1\n"), Catch::Contains("m.pfm:2: PFM height '-2'"));
    CHECK_THAT(error_of("PF\n3 2\n\nnan\n"), Catch::Contains("m.pfm:4: PFM scale 'nan'"));
    CHECK_THAT(error_of("PF\n3 2\n0\n"), Catch::Contains("PFM scale '0'"));
    CHECK_THAT(error_of("PF\n100000 100000\n-1\n"), Catch::Contains("out of range"));
    std::string cut = pfm("PF", 3, 2, 1.f, true, std::vector<float>(18, 1.f));
    cut.resize(cut.size() - 5);
    CHECK_THAT(error_of(cut), Catch::Contains("PFM data is short"));
    CHECK_THAT(error_of(""), Catch::Contains("not a PFM image"));
}
