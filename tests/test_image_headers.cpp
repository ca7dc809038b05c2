// Image headers that claim more pixels than their file could hold are refused before any
// pixel memory is taken (issue 34, defects 5 and 22): a 45-byte PNG claiming 16384^2 cost
// 3.2 GB before "no IDAT", and a 160 KB EXR claiming 20000^2 cost 4.7 GB.
#include <catch2/catch.hpp>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <vector>

#include "engine/core/error.h"
#include "engine/film/image_io.h"
#include "engine/scene/texture.h"
#include "test_util.h"

using namespace foton;

namespace {

void put32(std::vector<uint8_t>& b, uint32_t v) {
    for (int s = 24; s >= 0; s -= 8) b.push_back(uint8_t(v >> s));
}

// The 45-byte PNG of the report: signature, IHDR of w x h RGB 8-bit, IEND, no IDAT (stb
// does not check CRCs, so they are zero).
void write_png_header(const std::string& path, uint32_t w, uint32_t h) {
    std::vector<uint8_t> b = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    put32(b, 13);
    for (char c : {'I', 'H', 'D', 'R'}) b.push_back(uint8_t(c));
    put32(b, w);
    put32(b, h);
    for (uint8_t v : {8, 2, 0, 0, 0}) b.push_back(v);
    put32(b, 0);
    put32(b, 0);
    for (char c : {'I', 'E', 'N', 'D'}) b.push_back(uint8_t(c));
    put32(b, 0);
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
}

}  // namespace

TEST_CASE("image headers claiming more than their file holds are refused up front",
          "[image][bad-input][fast]") {
    test::TempDir dir;
    const std::string png = dir.file("huge.png");
    write_png_header(png, 16384, 16384);
    REQUIRE(std::filesystem::file_size(png) == 45);
    CHECK_THROWS_WITH(load_texture_image(png), Catch::Contains("a corrupt header"));
    CHECK_THROWS_WITH(read_png_mask(png, 16384, 16384), Catch::Contains("a corrupt header"));
    // Beyond the input limit (stb refuses it already): an error, never an allocation.
    write_png_header(png, 20000, 20000);
    CHECK_THROWS_AS(load_texture_image(png), InputError);

    // EXR headers with no pixels written: their line-offset tables alone (8 bytes a line).
    auto empty_exr = [&](int side) {
        const std::string exr = dir.file("huge" + std::to_string(side) + ".exr");
        Imf::Header h(side, side);
        h.channels().insert("R", Imf::Channel(Imf::HALF));
        { Imf::OutputFile f(exr.c_str(), h); }
        return exr;
    };
    const std::string report = empty_exr(20000);  // the report's 160 KB file
    CHECK(std::filesystem::file_size(report) < 400000);
    CHECK_THROWS_WITH(read_exr(report), Catch::Contains("out of range"));
    const std::string within = empty_exr(15000);  // under the limit, but not in 120 KB
    CHECK_THROWS_WITH(read_exr(within), Catch::Contains("a corrupt header"));
    // A real image still reads.
    Film small(3, 2);
    write_exr(dir.file("ok.exr"), small);
    CHECK(read_exr(dir.file("ok.exr")).width == 3);
}
