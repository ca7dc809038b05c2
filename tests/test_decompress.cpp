// Compressed meshes (engine/core/decompress.h): a PLY read from .ply.gz and .ply.xz equals the
// plain file's mesh, directly and through a pbrt-v4 plymesh; corrupt, truncated, foreign and
// oversized data are bad input naming the file (and the Shape's line in a pbrt file).
#include <lzma.h>
#include <zlib.h>
#include <catch2/catch.hpp>
#include <fstream>

#include "engine/core/decompress.h"
#include "engine/core/error.h"
#include "engine/scene/pbrt_loader.h"
#include "engine/scene/ply_reader.h"
#include "test_util.h"

using namespace foton;

namespace {

// A small ASCII PLY: a grid of quads split into triangles, long enough that compression
// spans several of zlib's internal blocks.
std::string grid_ply(int n) {
    std::string body;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x)
            body += std::to_string(x) + " " + std::to_string(y) + " " +
                    std::to_string((x * y) % 7) + "\n";
    int faces = 0;
    std::string f;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const int a = y * (n + 1) + x, b = a + 1, c = a + n + 1, d = c + 1;
            f +=
                "3 " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(d) + "\n";
            f +=
                "3 " + std::to_string(a) + " " + std::to_string(d) + " " + std::to_string(c) + "\n";
            faces += 2;
        }
    return "ply\nformat ascii 1.0\nelement vertex " + std::to_string((n + 1) * (n + 1)) +
           "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
           std::to_string(faces) + "\nproperty list uchar int vertex_indices\nend_header\n" + body +
           f;
}

void write(const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
}

std::string gzip_of(const std::string& s) {
    z_stream zs{};
    REQUIRE(deflateInit2(&zs, 6, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY) == Z_OK);
    std::string out(deflateBound(&zs, uLong(s.size())), '\0');
    zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(s.data()));
    zs.avail_in = uInt(s.size());
    zs.next_out = reinterpret_cast<Bytef*>(out.data());
    zs.avail_out = uInt(out.size());
    REQUIRE(deflate(&zs, Z_FINISH) == Z_STREAM_END);
    out.resize(zs.total_out);
    deflateEnd(&zs);
    return out;
}

std::string xz_of(const std::string& s) {
    std::string out(lzma_stream_buffer_bound(s.size()), '\0');
    std::size_t pos = 0;
    REQUIRE(lzma_easy_buffer_encode(
                6, LZMA_CHECK_CRC64, nullptr, reinterpret_cast<const uint8_t*>(s.data()), s.size(),
                reinterpret_cast<uint8_t*>(out.data()), &pos, out.size()) == LZMA_OK);
    out.resize(pos);
    return out;
}

std::string error_of(const std::string& path) {
    try {
        load_ply(path);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("compressed PLY: .ply.gz and .ply.xz read as the plain file", "[ply][fast]") {
    test::TempDir dir;
    const std::string ply = grid_ply(60);
    write(dir.file("grid.ply"), ply);
    write(dir.file("grid.ply.gz"), gzip_of(ply));
    write(dir.file("grid.ply.xz"), xz_of(ply));
    const TriangleMesh plain = load_ply(dir.file("grid.ply"));
    REQUIRE(plain.num_triangles() == 2 * 60 * 60);
    for (const char* name : {"grid.ply.gz", "grid.ply.xz"}) {
        const TriangleMesh m = load_ply(dir.file(name));
        INFO(name);
        CHECK(m.positions == plain.positions);
        CHECK(m.indices == plain.indices);
    }
    CHECK(is_compressed_input("a.PLY.GZ"));
    CHECK_FALSE(is_compressed_input("a.ply"));
    // Through a pbrt-v4 file, as pbrt-v4-scenes reference their meshes.
    const std::string pbrt =
        "LookAt 0 0 -5 0 0 0 0 1 0\nCamera \"perspective\"\nWorldBegin\n"
        "Shape \"plymesh\" \"string filename\" \"grid.ply.gz\"\n";
    const Scene s = parse_pbrt_scene(pbrt, dir.file("s.pbrt"), dir.path().string());
    REQUIRE(s.meshes.size() == 1);
    CHECK(s.meshes[0].num_triangles() == 2 * 60 * 60);
}

TEST_CASE("compressed pbrt-v4 includes: .pbrt.gz and .pbrt.xz read as the plain file",
          "[pbrt][fast]") {
    // pbrt-v4-scenes' hair scenes include their curves as a gzipped scene file.
    test::TempDir dir;
    const std::string curves =
        "Shape \"curve\" \"point3 P\" [0 0 0  0.3 1 0  0.6 -1 0  1 0 0] \"float width\" 0.1\n"
        "Shape \"curve\" \"point3 P\" [0 1 0  0.3 2 0  0.6 0 0  1 1 0] \"float width\" 0.1\n";
    write(dir.file("hair.pbrt.gz"), gzip_of(curves));
    write(dir.file("hair.pbrt.xz"), xz_of(curves));
    write(dir.file("half.pbrt.gz"), gzip_of(curves).substr(0, 20));
    auto scene = [&](const std::string& include) {
        return parse_pbrt_scene(
            "LookAt 0 0 -5 0 0 0 0 1 0\nCamera \"perspective\"\nWorldBegin\n"
            "Material \"hair\"\nInclude \"" +
                include + "\"\n",
            dir.file("s.pbrt"), dir.path().string());
    };
    for (const char* name : {"hair.pbrt.gz", "hair.pbrt.xz"}) {
        INFO(name);
        const Scene s = scene(name);
        std::size_t segments = 0;
        for (const CurveSet& c : s.curves) segments += c.size();
        CHECK(segments == 2);
    }
    try {
        scene("half.pbrt.gz");
        FAIL("no error");
    } catch (const InputError& e) {
        CHECK_THAT(e.what(), Catch::Contains("half.pbrt.gz") && Catch::Contains("truncated gzip"));
    }
}

TEST_CASE("compressed PLY: corrupt, truncated and foreign data are bad input",
          "[ply][bad-input][fast]") {
    test::TempDir dir;
    const std::string ply = grid_ply(40);
    const std::string gz = gzip_of(ply), xz = xz_of(ply);
    write(dir.file("half.ply.gz"), gz.substr(0, gz.size() / 2));
    write(dir.file("half.ply.xz"), xz.substr(0, xz.size() / 2));
    std::string flipped = gz;
    flipped[gz.size() / 2] = char(flipped[gz.size() / 2] ^ 0x5a);
    write(dir.file("flipped.ply.gz"), flipped);
    write(dir.file("plain.ply.gz"), ply);  // not compressed at all
    write(dir.file("plain.ply.xz"), ply);
    CHECK_THAT(error_of(dir.file("half.ply.gz")), Catch::Contains("truncated gzip data"));
    CHECK_THAT(error_of(dir.file("half.ply.xz")), Catch::Contains("truncated xz data"));
    CHECK_THAT(error_of(dir.file("flipped.ply.gz")), Catch::Contains("corrupt gzip data"));
    CHECK_THAT(error_of(dir.file("plain.ply.gz")), Catch::Contains("corrupt gzip data"));
    CHECK_THAT(error_of(dir.file("plain.ply.xz")), Catch::Contains("not xz data"));
    CHECK_THAT(error_of(dir.file("half.ply.gz")), Catch::Contains("half.ply.gz"));
    // A decompression bomb stops at the limit.
    const std::string zeros(std::size_t(8) << 20, '\0');
    try {
        decompress_input(gzip_of(zeros), "bomb.gz", uint64_t(2) << 20);
        FAIL("no error");
    } catch (const InputError& e) {
        CHECK_THAT(e.what(), Catch::Contains("more than the 2 MiB allowed"));
    }
    // In a pbrt-v4 file: the Shape's file and line.
    const std::string pbrt =
        "LookAt 0 0 -5 0 0 0 0 1 0\nCamera \"perspective\"\nWorldBegin\n"
        "Shape \"plymesh\" \"string filename\" \"half.ply.gz\"\n";
    try {
        parse_pbrt_scene(pbrt, dir.file("s.pbrt"), dir.path().string());
        FAIL("no error");
    } catch (const InputError& e) {
        CHECK_THAT(e.what(), Catch::Contains("s.pbrt:4:"));
        CHECK_THAT(e.what(), Catch::Contains("truncated gzip data"));
    }
}
