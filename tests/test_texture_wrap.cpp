// Image textures beyond their edges: repeating, clamped, mirrored (glTF's MIRRORED_REPEAT) and
// black (pbrt-v4's "black"), in every lookup (bilinear, alpha, nearest, EWA), and as glTF's
// samplers and pbrt-v4's `wrap` ask for them.
#include <stb/stb_image_write.h>

#include <catch2/catch.hpp>
#include <fstream>

#include "engine/core/error.h"
#include "engine/scene/mesh_file.h"
#include "engine/scene/texture.h"
#include "engine/scene/xml_loader.h"
#include "test_util.h"

using namespace foton;

namespace {

// Two texels in a row, 0.2 and 0.8 (alpha 0.5 and 1), one row high.
TextureImage two_texels(TextureWrap wrap) {
    TextureImage img;
    img.width = 2;
    img.height = 1;
    img.texels = {RGB{0.2f}, RGB{0.8f}};
    img.alpha = {0.5f, 1.f};
    img.wrap_s = img.wrap_t = wrap;
    return img;
}

}  // namespace

TEST_CASE("texture wrap: texel indices past the edges under each mode", "[texture]") {
    bool out = false;
    auto idx = [&](double i, TextureWrap w) {
        out = false;
        return wrapped_texel_index(i, 4, w, out);
    };
    // Repeat: the image again; mirror: 0 1 2 3 3 2 1 0 0 1 ...; clamp: the edge texel.
    CHECK(idx(-1, TextureWrap::Repeat) == 3);
    CHECK(idx(4, TextureWrap::Repeat) == 0);
    CHECK(idx(-1, TextureWrap::Mirror) == 0);
    CHECK(idx(-4, TextureWrap::Mirror) == 3);
    CHECK(idx(-5, TextureWrap::Mirror) == 3);
    CHECK(idx(4, TextureWrap::Mirror) == 3);
    CHECK(idx(5, TextureWrap::Mirror) == 2);
    CHECK(idx(8, TextureWrap::Mirror) == 0);
    CHECK(idx(-3, TextureWrap::Clamp) == 0);
    CHECK(idx(7, TextureWrap::Clamp) == 3);
    CHECK(!out);
    CHECK(idx(2, TextureWrap::Black) == 2);
    CHECK(!out);
    idx(4, TextureWrap::Black);
    CHECK(out);
    idx(-1, TextureWrap::Black);
    CHECK(out);
    // Far outside: in range, no overflow.
    for (TextureWrap w :
         {TextureWrap::Repeat, TextureWrap::Mirror, TextureWrap::Clamp, TextureWrap::Black}) {
        for (double i : {1e30, -1e30, 1e9 + 0.5}) {
            const int k = idx(i, w);
            CHECK(k >= 0);
            CHECK(k < 4);
        }
    }
    TextureWrap w;
    CHECK(parse_texture_wrap("mirror", w));
    CHECK(w == TextureWrap::Mirror);
    CHECK(!parse_texture_wrap("octahedralsphere", w));
}

TEST_CASE("texture wrap: bilinear, alpha, nearest and EWA lookups read the mode", "[texture]") {
    struct Case {
        TextureWrap wrap;
        float beyond_right, beyond_left, at_right_edge;  // u = 1.25, -0.25, 1.0
    };
    // Texel centres at u = 0.25 (0.2) and 0.75 (0.8). u = 1.25 is one texel past the right
    // edge: repeat reads 0.2, clamp and mirror 0.8, black 0; u = 1 is halfway between the
    // right texel and the one past it.
    for (const Case& c :
         {Case{TextureWrap::Repeat, 0.2f, 0.8f, 0.5f}, Case{TextureWrap::Clamp, 0.8f, 0.2f, 0.8f},
          Case{TextureWrap::Mirror, 0.8f, 0.2f, 0.8f}, Case{TextureWrap::Black, 0.f, 0.f, 0.4f}}) {
        const TextureImage img = two_texels(c.wrap);
        INFO("wrap " << int(c.wrap));
        CHECK(img.bilinear({1.25f, 0.5f}).r == Approx(c.beyond_right));
        CHECK(img.bilinear({-0.25f, 0.5f}).r == Approx(c.beyond_left));
        CHECK(img.bilinear({1.f, 0.5f}).r == Approx(c.at_right_edge));
        CHECK(img.bilinear({0.5f, 0.5f}).r == Approx(0.5f));
        CHECK(img.nearest({1.3f, 0.5f}).r == Approx(c.beyond_right));
        // Alpha 0.5 and 1: the same weights (black: no coverage beyond the edge).
        const float alpha_right = c.wrap == TextureWrap::Repeat  ? 0.5f
                                  : c.wrap == TextureWrap::Black ? 0.f
                                                                 : 1.f;
        CHECK(img.bilinear_alpha({1.25f, 0.5f}) == Approx(alpha_right));
        // EWA over a tiny ellipse is the nearby texels' average: past the edge it reads the
        // mode's texels too.
        const RGB e = img.ewa({1.25f, 0.5f}, {1e-3f, 0.f}, {0.f, 1e-3f}, 8.f);
        CHECK(e.r == Approx(c.beyond_right).margin(0.02));
    }
}

TEST_CASE("texture wrap: glTF samplers and pbrt-v4's wrap set the image's modes",
          "[texture][gltf][pbrt]") {
    test::TempDir dir;
    const unsigned char px[] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 128, 128, 128};
    REQUIRE(stbi_write_png(dir.file("t.png").c_str(), 2, 2, 3, px, 6) != 0);
    const float buf[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, -1, 2, 2, 2, 2, -1, -1, -1};
    const uint16_t idx[] = {0, 1, 2, 0, 2, 3};
    {
        std::ofstream bin(dir.file("q.bin"), std::ios::binary);
        bin.write(reinterpret_cast<const char*>(buf), sizeof buf);
        bin.write(reinterpret_cast<const char*>(idx), sizeof idx);
    }
    auto write = [&](const std::string& sampler) {
        std::ofstream(dir.file("q.gltf")) << R"({"asset": {"version": "2.0"},
  "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2,
    "material": 0}]}],
  "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
  "textures": [{"source": 0, "sampler": 0}], "images": [{"uri": "t.png"}],
  "samplers": [)" << sampler << R"(],
  "buffers": [{"uri": "q.bin", "byteLength": 92}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                  {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                  {"buffer": 0, "byteOffset": 80, "byteLength": 12}],
  "accessors": [
    {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3"},
    {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
    {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}]})";
    };
    write(R"({"wrapS": 33071, "wrapT": 33648, "magFilter": 9728})");
    const MeshFile f = load_mesh_file(dir.file("q.gltf"));
    REQUIRE(f.embedded_images.size() == 1);
    const TextureImage& img = f.embedded_images.begin()->second;
    CHECK(img.wrap_s == TextureWrap::Clamp);
    CHECK(img.wrap_t == TextureWrap::Mirror);
    bool noted = false;
    for (const std::string& n : f.notes) noted |= n.find("magFilter NEAREST") != n.npos;
    CHECK(noted);
    write(R"({"wrapS": 1234})");
    CHECK_THROWS_WITH(load_mesh_file(dir.file("q.gltf")), Catch::Contains("q.gltf") &&
                                                              Catch::Contains("sampler 0") &&
                                                              Catch::Contains("wrap mode 1234"));

    // pbrt-v4: "clamp" and "black" are read (one image per mode), the octahedral sphere not.
    auto pbrt = [&](const std::string& wraps) {
        std::ofstream(dir.file("w.pbrt")) << R"(LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic"
Film "rgb" "integer xresolution" 8 "integer yresolution" 8
WorldBegin
LightSource "distant" "point3 to" [0 0 -1]
)" << wraps << R"(Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 1 1 0 0 1 0]
  "point2 uv" [-1 -1 2 -1 2 2 -1 2] "integer indices" [0 1 2 0 2 3]
)";
    };
    pbrt(R"(Texture "c" "spectrum" "imagemap" "string filename" "t.png" "string wrap" "clamp"
Texture "b" "spectrum" "imagemap" "string filename" "t.png" "string wrap" "black"
Texture "m" "spectrum" "mix" "texture tex1" "c" "texture tex2" "b"
Material "diffuse" "texture reflectance" "m"
)");
    const Scene s = load_scene(dir.file("w.pbrt"));
    REQUIRE(s.texture_images.size() == 2);
    CHECK(s.texture_images[0].wrap_s == TextureWrap::Clamp);
    CHECK(s.texture_images[1].wrap_t == TextureWrap::Black);
    for (const char* bad : {"octahedralsphere", "mirror"}) {
        pbrt(std::string(
                 R"(Texture "c" "spectrum" "imagemap" "string filename" "t.png" "string wrap" ")") +
             bad + "\"\nMaterial \"diffuse\" \"texture reflectance\" \"c\"\n");
        CHECK_THROWS_WITH(load_scene(dir.file("w.pbrt")),
                          Catch::Contains("w.pbrt:6") && Catch::Contains("texture wrap"));
    }
}
