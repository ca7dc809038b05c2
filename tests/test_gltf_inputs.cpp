// Hostile glTF files (issue 34, defects 1-4): each once crashed or exhausted the process; now
// each is an InputError naming the file, before the memory or the stack is spent.
#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <cstring>
#include <fstream>
#include <string>

#include "engine/core/error.h"
#include "engine/scene/gltf_inputs.h"
#include "engine/scene/mesh_file.h"
#include "test_util.h"

using namespace foton;

namespace {

std::string base64(const std::string& bytes) {
    static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    std::size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16 |
                           uint32_t(uint8_t(bytes[i + 1])) << 8 | uint8_t(bytes[i + 2]);
        for (int s = 18; s >= 0; s -= 6) out += k[(v >> s) & 63];
    }
    if (i < bytes.size()) {
        uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) v |= uint32_t(uint8_t(bytes[i + 1])) << 8;
        out += k[(v >> 18) & 63];
        out += k[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? k[(v >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

// One triangle's positions (3 x VEC3 float), 36 bytes.
std::string triangle_bytes() {
    const float p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    return std::string(reinterpret_cast<const char*>(p), sizeof p);
}

// A glTF of one triangle whose buffer is `uri`, with `nodes` and `extra` (more top-level
// members) spliced in.
std::string gltf(const std::string& uri, const std::string& nodes = R"([{"mesh": 0}])",
                 const std::string& extra = "") {
    return R"({"asset": {"version": "2.0"}, "nodes": )" + nodes +
           R"(, "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
  "buffers": [{"uri": ")" +
           uri + R"(", "byteLength": 36}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 0]}])" +
           extra + "}";
}

std::string embedded_triangle() {
    return "data:application/octet-stream;base64," + base64(triangle_bytes());
}

std::string load_error(const std::string& path) {
    try {
        load_gltf(path);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("glTF: JSON nested 20,000 deep is refused before the parser recurses",
          "[gltf][security][fast]") {
    test::TempDir dir;
    const std::string deep = std::string(20000, '[') + std::string(20000, ']');
    std::ofstream(dir.file("deep.gltf"))
        << gltf(embedded_triangle(), R"([{"mesh": 0}])", R"(, "extras": {"x": )" + deep + "}");
    const std::string e = load_error(dir.file("deep.gltf"));
    CHECK_THAT(e, Catch::Contains("deep.gltf") && Catch::Contains("nested deeper than 256"));
    // Brackets inside strings do not count; the shallow file loads.
    CHECK(json_nesting_depth(R"({"a": "[[[[{{{{", "b": [1, [2]]})") == 3);
    std::ofstream(dir.file("ok.gltf")) << gltf(embedded_triangle());
    CHECK(load_gltf(dir.file("ok.gltf")).parts.size() == 1);
}

TEST_CASE("glTF: a node graph that multiplies its placements is refused",
          "[gltf][security][fast]") {
    test::TempDir dir;
    // Node i lists node i + 1 twice: 2^24 copies of the last node's triangle.
    std::string nodes = "[";
    for (int i = 0; i < 24; ++i)
        nodes += "{\"children\": [" + std::to_string(i + 1) + ", " + std::to_string(i + 1) + "]},";
    nodes += R"({"mesh": 0}])";
    std::ofstream(dir.file("dag.gltf"))
        << gltf(embedded_triangle(), nodes, R"(, "scenes": [{"nodes": [0]}], "scene": 0)");
    CHECK_THAT(load_error(dir.file("dag.gltf")),
               Catch::Contains("dag.gltf") && Catch::Contains("places more than"));
}

TEST_CASE("glTF: buffers are regular files under the model's folder, nothing else",
          "[gltf][security][fast]") {
    test::TempDir dir;
    std::filesystem::create_directories(dir.path() / "model");
    std::ofstream(dir.file("secret.bin"), std::ios::binary) << triangle_bytes();
    std::ofstream(dir.file("model/tri.bin"), std::ios::binary) << triangle_bytes();
    auto error_for = [&](const std::string& uri) {
        std::ofstream(dir.file("model/m.gltf")) << gltf(uri);
        return load_error(dir.file("model/m.gltf"));
    };
    CHECK(error_for("tri.bin").empty());
    // Percent-encoded and plain ../ leave the folder.
    CHECK_THAT(error_for("%2e%2e/secret.bin"), Catch::Contains("outside the model's folder"));
    CHECK_THAT(error_for("../secret.bin"), Catch::Contains("outside the model's folder"));
    // An absolute URI is joined to the folder, so it names nothing there.
    CHECK_THAT(error_for(dir.file("secret.bin")), Catch::Contains("File not found"));
    // A directory, and a FIFO (which would block the read forever).
    CHECK_THAT(error_for("."), Catch::Contains("m.gltf") && Catch::Contains("it is a directory"));
    REQUIRE(mkfifo(dir.file("model/fifo").c_str(), 0600) == 0);
    CHECK_THAT(error_for("fifo"), Catch::Contains("not a regular file"));
    // A symlink in the folder that points out of it.
    std::filesystem::create_symlink(dir.file("secret.bin"), dir.file("model/link.bin"));
    CHECK_THAT(error_for("link.bin"), Catch::Contains("outside the model's folder"));
}

TEST_CASE("glTF: an embedded image whose header claims 16384^2 is refused before decoding",
          "[gltf][security][fast]") {
    test::TempDir dir;
    // A PNG signature and an IHDR chunk claiming 16384 x 16384 RGB, nothing after it.
    std::string png = "\x89PNG\r\n\x1a\n";
    const unsigned char ihdr[] = {0, 0,    0, 13, 'I', 'H', 'D', 'R', 0,    0,    0x40, 0,   0,
                                  0, 0x40, 0, 8,  2,   0,   0,   0,   0x8b, 0x4b, 0x47, 0x1f};
    png.append(reinterpret_cast<const char*>(ihdr), sizeof ihdr);
    const std::string image = R"(, "materials": [{"pbrMetallicRoughness": {"baseColorTexture":
        {"index": 0}}}], "textures": [{"source": 0}], "images": [{"uri":
        "data:image/png;base64,)" +
                              base64(png) + "\"}]";
    std::ofstream(dir.file("img.gltf")) << gltf(embedded_triangle(), R"([{"mesh": 0}])", image);
    CHECK_THAT(load_error(dir.file("img.gltf")),
               Catch::Contains("img.gltf") && Catch::Contains("16384x16384"));
}

TEST_CASE("glTF: an image file outside the model's folder or missing is an error saying why",
          "[gltf][security][fast]") {
    test::TempDir dir;
    std::filesystem::create_directories(dir.path() / "model");
    std::ofstream(dir.file("outside.png"), std::ios::binary) << "not read";
    auto error_for = [&](const std::string& uri) {
        const std::string image = R"(, "materials": [{"pbrMetallicRoughness": {"baseColorTexture":
            {"index": 0}}}], "textures": [{"source": 0}], "images": [{"uri": ")" +
                                  uri + "\"}]";
        // The triangle wears the material, so its texture is read.
        std::string text = gltf(embedded_triangle(), R"([{"mesh": 0}])", image);
        const std::string prim = R"({"POSITION": 0})";
        text.replace(text.find(prim), prim.size(), prim + R"(, "material": 0)");
        std::ofstream(dir.file("model/m.gltf")) << text;
        return load_error(dir.file("model/m.gltf"));
    };
    CHECK_THAT(error_for("../outside.png"),
               Catch::Contains("m.gltf") && Catch::Contains("'../outside.png' could not be read") &&
                   Catch::Contains("outside the model's folder"));
    CHECK_THAT(error_for("nothing.png"), Catch::Contains("'nothing.png' could not be read") &&
                                             Catch::Contains("File not found"));
}
