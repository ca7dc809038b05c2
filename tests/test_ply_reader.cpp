// The PLY reader: ASCII and both binary byte orders give the same mesh (positions, normals,
// uv, polygons fanned), other elements are read past, and bad files fail at their header
// line, data line or byte offset.
#include <catch2/catch.hpp>
#include <cstring>

#include "engine/core/error.h"
#include "engine/scene/ply_reader.h"

using namespace foton;

namespace {

const char* kHeader =
    "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "property float nx\nproperty float ny\nproperty float nz\nproperty float s\n"
    "property float t\nelement face 1\nproperty list uchar int vertex_indices\n"
    "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n";

const float kVerts[4][8] = {{0, 0, 0, 0, 0, 1, 0, 0},
                            {1, 0, 0, 0, 0, 1, 1, 0},
                            {1, 1, 0, 0, 0, 1, 1, 1},
                            {0, 1, 0, 0, 0, 1, 0, 1}};

std::string binary(bool big) {
    std::string s = std::string("ply\nformat ") +
                    (big ? "binary_big_endian" : "binary_little_endian") + " 1.0\n" + kHeader;
    auto put = [&](const void* p, std::size_t n) {
        unsigned char b[8];
        std::memcpy(b, p, n);
        if (big)
            for (std::size_t i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
        s.append(reinterpret_cast<const char*>(b), n);
    };
    for (const auto& v : kVerts)
        for (float f : v) put(&f, 4);
    const unsigned char four = 4;
    s.push_back(char(four));
    for (int32_t i : {0, 1, 2, 3}) put(&i, 4);
    for (int32_t i : {0, 1}) put(&i, 4);
    return s;
}

std::string ascii() {
    std::string s = std::string("ply\nformat ascii 1.0\ncomment made by a test\n") + kHeader;
    for (const auto& v : kVerts) {
        for (float f : v) s += std::to_string(f) + " ";
        s += "\n";
    }
    return s + "4 0 1 2 3\n0 1\n";
}

std::string error_of(const std::string& bytes) {
    try {
        parse_ply(bytes, "m.ply");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("PLY: ASCII and binary files read the same mesh", "[ply][fast]") {
    for (const std::string& file : {ascii(), binary(false), binary(true)}) {
        const TriangleMesh m = parse_ply(file, "m.ply");
        REQUIRE(m.num_vertices() == 4);
        REQUIRE(m.num_triangles() == 2);  // the quad, fanned
        CHECK(m.indices == std::vector<uint32_t>{0, 1, 2, 0, 2, 3});
        REQUIRE(m.normals.size() == 12);
        CHECK(m.normals[2] == 1.f);
        REQUIRE(m.uvs.size() == 8);
        CHECK(m.uvs[4] == 1.f);
        CHECK(m.uvs[5] == 1.f);
        CHECK(m.vertex(2).y == 1.f);
    }
}

TEST_CASE("PLY: bad files fail at their line or byte", "[ply][fast]") {
    const std::string ok = ascii();
    const std::string bin = binary(false);
    const std::pair<std::string, std::string> cases[] = {
        {"obj\n", "m.ply:1: not a PLY file"},
        {"ply\nformat ascii 2.0\nend_header\n", "m.ply:2: unsupported PLY version"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty quad x\nend_header\n",
         "m.ply:4: unknown property type 'quad'"},
        {"ply\nformat ascii 1.0\nelement vertex 99999999\nproperty float x\nend_header\n",
         "m.ply:3: element 'vertex' count exceeds the file size"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", "no end_header"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
         "end_header\n0 0\n",
         "m.ply:3: the vertex element needs x, y and z"},
        {ok.substr(0, ok.size() - 12), "unexpected end of file"},
        {bin.substr(0, bin.size() - 3), "m.ply: byte "},
        {[&] {
             std::string s = ok;
             s.replace(s.find("4 0 1 2 3"), 9, "3 0 1 7  ");
             return s;
         }(),
         "a face refers to vertex 7 of 4"},
        {[&] {
             std::string s = ok;
             s.replace(s.rfind("1.000000 1.000000 0.000000"), 8, "nan     ");
             return s;
         }(),
         "m.ply:21: 'nan' is not a finite number"},
    };
    for (const auto& [bytes, want] : cases) {
        INFO(want);
        const std::string got = error_of(bytes);
        INFO("got: " << got);
        CHECK(got.find(want) != std::string::npos);
    }
}
