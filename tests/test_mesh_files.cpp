// Mesh files with their materials, placed by the XML <triangle_mesh src=...>: OBJ with MTL
// (diffuse colours, image maps, Phong, mirror, glass, emission), glTF 2.0 (node transforms,
// baseColorFactor and baseColorTexture, metallic-roughness, emission) and PLY. Textured
// quads render their texture's colours pixel for pixel; bad files are errors at their
// file and line (or glTF object).
#include <stb/stb_image_write.h>

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>

#include "engine/accel/intersector.h"
#include "engine/core/error.h"
#include "engine/scene/mesh_file.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/render.h"
#include "flat_quad_scene.h"
#include "test_util.h"

using namespace foton;
using test::worst_pixel;
using test::write_scene;

namespace {

// A 2 x 2 PNG: red, green / blue, grey (sRGB 128: linear 0.2158).
void write_texture(const std::string& path) {
    const unsigned char px[] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 128, 128, 128};
    REQUIRE(stbi_write_png(path.c_str(), 2, 2, 3, px, 6) != 0);
}

const Material& material_of_part(const Scene& s, std::size_t i) {
    return s.material_of(uint32_t(i));
}

}  // namespace

TEST_CASE("OBJ + MTL: materials by face and a textured half render as the file says",
          "[obj][texture][mesh-file]") {
    test::TempDir dir;
    write_texture(dir.file("t.png"));
    // Left half [0, 0.5] textured (uv = position), right half flat blue-green.
    std::ofstream(dir.file("quad.mtl"))
        << "# made by the test\nnewmtl tex\nKd 1 1 1\nmap_Kd t.png\n"
        << "Ka 0.1 0.1 0.1\nmap_Ks spec.png\n"
        << "newmtl flat\nKd 0.2 0.4 0.6\nillum 1\nPs 0.5\n";
    std::ofstream(dir.file("quad.obj"))
        << "mtllib quad.mtl\n"
           "v 0 0 0\nv 0.5 0 0\nv 0.5 1 0\nv 0 1 0\nv 1 0 0\nv 1 1 0\n"
           "vt 0 0\nvt 0.5 0\nvt 0.5 1\nvt 0 1\nvt 1 0\nvt 1 1\n"
           "usemtl tex\nf 1/1 2/2 3/3 4/4\nusemtl flat\nf 2/2 5/5 6/6 3/3\n";
    write_scene(dir.file("s.xml"), R"(<triangle_mesh src="quad.obj"/>)");
    const Scene s = load_scene(dir.file("s.xml"));
    REQUIRE(s.objects.size() == 2);
    CHECK(material_of_part(s, 0).texture >= 0);
    CHECK(material_of_part(s, 1).bsdf.lobe(0).color.b == Approx(0.6f));
    REQUIRE(s.texture_images.size() == 1);
    // What the file says and foton leaves out is listed, with its line.
    auto warned = [&](const std::string& text) {
        for (const std::string& w : s.warnings)
            if (w.find(text) != std::string::npos) return true;
        return false;
    };
    CHECK(warned("quad.mtl:5: 'Ka' ignored"));
    CHECK(warned("quad.mtl:6: 'map_Ks' ignored"));
    CHECK(warned("quad.mtl:10: unknown MTL statement 'Ps' ignored"));
    const TextureImage& img = s.texture_images[0];
    const double worst = worst_pixel(dir.file("s.xml"), [&](float x, float y) {
        return x < 0.5f ? img.bilinear({x, y}) : RGB{0.2f, 0.4f, 0.6f};
    });
    INFO("worst pixel difference " << worst);
    CHECK(worst < 0.02);
    // The object's own <material> replaces the file's, and says so.
    write_scene(dir.file("o.xml"), R"(<triangle_mesh src="quad.obj">
      <material type="lambert"><reflectance r="0.3" g="0.3" b="0.3"/></material></triangle_mesh>)");
    const Scene o = load_scene(dir.file("o.xml"));
    CHECK(o.materials.size() == 1);
    CHECK(o.warnings.back().find("are replaced by the object's <material>") != std::string::npos);
}

TEST_CASE("MTL: illumination models become foton's lobes", "[obj][mesh-file][fast]") {
    std::vector<std::string> notes;
    const auto m = parse_mtl(
        "newmtl phong\nKd 0.5 0.5 0.5\nKs 0.3 0.3 0.3\nNs 50\nillum 2\n"
        "newmtl mirror\nKd 0 0 0\nKs 0.9 0.9 0.9\nillum 3\n"
        "newmtl glass\nNi 1.33\nillum 7\nd 0.5\n"
        "newmtl lamp\nKd 0.1 0.1 0.1\nKe 5 4 3\n"
        "newmtl ghost\nKd 0.5 0.5 0.5\nd 0.3\n",
        "m.mtl", ".", notes);
    REQUIRE(m.size() == 5);
    CHECK(m.at("phong").exponent == 50.f);
    CHECK(m.at("mirror").mirror);
    CHECK(m.at("glass").glass);
    CHECK(m.at("glass").ior == Approx(1.33f));
    CHECK(m.at("lamp").emission.g == 4.f);
    CHECK(m.at("ghost").alpha == Approx(0.3f));  // dissolve: coverage
    CHECK(m.at("glass").alpha == 1.f);
    Scene s;
    MeshFile none;
    std::map<std::string, uint32_t> images;
    const Material phong = s.materials[add_file_material(s, m.at("phong"), none, images)];
    REQUIRE(phong.bsdf.size() == 2);
    CHECK(phong.bsdf.lobe(1).type == LobeType::Phong);
    const Material mirror = s.materials[add_file_material(s, m.at("mirror"), none, images)];
    CHECK(mirror.bsdf.has_delta());
    const Material glass = s.materials[add_file_material(s, m.at("glass"), none, images)];
    CHECK(glass.bsdf.lobe(0).type == LobeType::Dielectric);
    const Material lamp = s.materials[add_file_material(s, m.at("lamp"), none, images)];
    CHECK(lamp.emission.r == 5.f);
    // Bad MTL input, at its line.
    auto fails = [&](const std::string& text, const std::string& what) {
        std::vector<std::string> n;
        try {
            parse_mtl(text, "bad.mtl", ".", n);
            FAIL("accepted: " << text);
        } catch (const InputError& e) {
            CHECK_THAT(e.what(), Catch::Contains(what));
        }
    };
    fails("Kd 1 1 1\n", "bad.mtl:1: 'Kd' before any newmtl");
    fails("newmtl a\nKd 1 x 1\n", "bad.mtl:2: malformed number 'x'");
    fails("newmtl a\nKd 2 2 2\n", "bad.mtl:2: Kd above 1");
    fails("newmtl a\nillum 2.5\n", "bad.mtl:2: illum must be an integer");
    fails("newmtl a\nmap_Kd -bm 2 t.png\n", "bad.mtl:2: map_Kd option '-bm'");
    fails("newmtl a\nNs -3\n", "bad.mtl:2: Ns must be in");
    fails("newmtl a\nPm 1.5\n", "bad.mtl:2: Pm must be in [0, 1]");
    // The PBR extension's Pm and Pr: glTF's metallic-roughness reading (a rough conductor of
    // the base colour's reflectance beside what is left of the Lambert).
    const auto pbr = parse_mtl("newmtl gold\nKd 1 0.8 0.3\nPm 0.75\nPr 0.5\n", "p.mtl", ".", notes);
    const Material gold = s.materials[add_file_material(s, pbr.at("gold"), none, images)];
    REQUIRE(gold.bsdf.size() == 2);
    CHECK(gold.bsdf.lobe(0).color.r == Approx(0.25f));
    CHECK(gold.bsdf.lobe(1).type == LobeType::Microfacet);
    CHECK(gold.bsdf.lobe(1).dist.alpha == Approx(0.25f));
    CHECK(gold.bsdf.lobe(1).color.g == Approx(0.75f));
}

namespace {

// A glTF file: the quad split in two primitives (textured left half, flat right half) under
// a node translated by (0.25, 0, 0) whose child is scaled by 0.5 in x, so the file's
// [-0.5, 1.5] x [0, 1] lands on [0, 1]^2.
void write_gltf(const test::TempDir& dir, const std::string& extra_material = "") {
    // Positions (2 x 4 vertices), uvs (glTF's v runs down), indices (2 x 6).
    const float pos[] = {-0.5f, 0, 0, 0.5f, 0, 0, 0.5f, 1, 0, -0.5f, 1, 0,
                         0.5f,  0, 0, 1.5f, 0, 0, 1.5f, 1, 0, 0.5f,  1, 0};
    const float uv[] = {0, 1, 0.5f, 1, 0.5f, 0, 0, 0};
    const uint16_t idx[] = {0, 1, 2, 0, 2, 3, 0, 1, 2, 0, 2, 3};
    std::ofstream bin(dir.file("quad.bin"), std::ios::binary);
    bin.write(reinterpret_cast<const char*>(pos), sizeof pos);
    bin.write(reinterpret_cast<const char*>(uv), sizeof uv);
    bin.write(reinterpret_cast<const char*>(idx), sizeof idx);
    bin.close();
    std::ofstream(dir.file("quad.gltf")) << R"({
  "asset": {"version": "2.0"},
  "scene": 0,
  "scenes": [{"nodes": [0]}],
  "nodes": [{"translation": [0.25, 0, 0], "children": [1]},
            {"scale": [0.5, 1, 1], "mesh": 0}],
  "meshes": [{"primitives": [
    {"attributes": {"POSITION": 0, "TEXCOORD_0": 2}, "indices": 4, "material": 0},
    {"attributes": {"POSITION": 1}, "indices": 5, "material": 1}]}],
  "materials": [
    {"name": "tex", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0}},
    {"name": "flat", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1], "metallicFactor": 0})" +
                                                extra_material +
                                                R"(}],
  "textures": [{"source": 0}],
  "images": [{"uri": "t.png"}],
  "buffers": [{"uri": "quad.bin", "byteLength": 152}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 96},
                  {"buffer": 0, "byteOffset": 96, "byteLength": 32},
                  {"buffer": 0, "byteOffset": 128, "byteLength": 24}],
  "accessors": [
    {"bufferView": 0, "byteOffset": 0, "componentType": 5126, "count": 4, "type": "VEC3"},
    {"bufferView": 0, "byteOffset": 48, "componentType": 5126, "count": 4, "type": "VEC3"},
    {"bufferView": 1, "byteOffset": 0, "componentType": 5126, "count": 4, "type": "VEC2"},
    {"bufferView": 1, "byteOffset": 0, "componentType": 5126, "count": 4, "type": "VEC2"},
    {"bufferView": 2, "byteOffset": 0, "componentType": 5123, "count": 6, "type": "SCALAR"},
    {"bufferView": 2, "byteOffset": 12, "componentType": 5123, "count": 6, "type": "SCALAR"}]
})";
}

// Replaces text in a file, once per call (the replaced text must be there); written back when
// it goes out of scope.
class GltfEdit {
  public:
    explicit GltfEdit(std::string path) : path_(std::move(path)) {
        std::ifstream in(path_);
        text_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    ~GltfEdit() { std::ofstream(path_) << text_; }
    void operator()(const std::string& from, const std::string& to) {
        const std::size_t at = text_.find(from);
        REQUIRE(at != std::string::npos);
        text_.replace(at, from.size(), to);
    }

  private:
    std::string path_, text_;
};

// write_gltf's quad with a second 2 x 2 image, file `png` of texels `rgb` (`channels` bytes
// each), as texture 1 and `extensions` (a JSON object's members) on the textured material.
void write_gltf_with_texture(const test::TempDir& dir, const unsigned char* rgb,
                             const std::string& png, const std::string& extensions,
                             int channels = 3) {
    REQUIRE(stbi_write_png(dir.file(png).c_str(), 2, 2, channels, rgb, 2 * channels) != 0);
    write_gltf(dir);
    GltfEdit edit(dir.file("quad.gltf"));
    edit(R"("baseColorTexture": {"index": 0}, "metallicFactor": 0})",
         R"("baseColorTexture": {"index": 0}, "metallicFactor": 0}, "extensions": {)" + extensions +
             "}");
    edit(R"("textures": [{"source": 0}])", R"("textures": [{"source": 0}, {"source": 1}])");
    edit(R"("images": [{"uri": "t.png"}])",
         R"("images": [{"uri": "t.png"}, {"uri": ")" + png + R"("}])");
}

// The quad of write_gltf_with_texture rendered head-on (write_scene): the worst pixel against
// `want` on its textured half (given the base colour image and the second one, `second`,
// whichever was decoded first), the flat half its Lambert 0.96 and reflection 0.01.
double worst_textured_half(
    const test::TempDir& dir, const std::string& second,
    const std::function<RGB(const TextureImage&, const TextureImage&, float, float)>& want) {
    write_scene(dir.file("s.xml"), R"(<triangle_mesh src="quad.gltf"/>)");
    const Scene s = load_scene(dir.file("s.xml"));
    REQUIRE(s.texture_images.size() == 2);
    const bool second_first = s.texture_images[0].path.find(second) != std::string::npos;
    const TextureImage& base = s.texture_images[second_first ? 1 : 0];
    const TextureImage& tex = s.texture_images[second_first ? 0 : 1];
    return worst_pixel(dir.file("s.xml"), [&](float x, float y) {
        return x >= 0.5f ? RGB{0.2f, 0.4f, 0.6f} * 0.96f + RGB{0.01f} : want(base, tex, x, y);
    });
}

}  // namespace

TEST_CASE("glTF: node transforms, base colour factors and textures render as the file says",
          "[gltf][texture][mesh-file]") {
    test::TempDir dir;
    write_texture(dir.file("t.png"));
    write_gltf(dir);
    write_scene(dir.file("s.xml"), R"(<triangle_mesh src="quad.gltf"/>)");
    const Scene s = load_scene(dir.file("s.xml"));
    REQUIRE(s.objects.size() == 2);
    CHECK(s.bounds().lo.x == Approx(0.f));
    CHECK(s.bounds().hi.x == Approx(1.f));
    REQUIRE(s.texture_images.size() == 1);
    const TextureImage& img = s.texture_images[0];
    // The left primitive's uv: u = 2x over [0, 0.5], v (foton's, up) = y. glTF's dielectric
    // reflects F0 = 0.04 (index 1.5) by GGX of alpha = roughness^2 = 1 beside the diffuse
    // 0.96 albedo: head-on under irradiance pi, F D G / 4 x pi = 0.04 / (4 pi) x pi = 0.01.
    const double worst = worst_pixel(dir.file("s.xml"), [&](float x, float y) {
        return (x < 0.5f ? img.bilinear({x, y}) : RGB{0.2f, 0.4f, 0.6f}) * 0.96f + RGB{0.01f};
    });
    INFO("worst pixel difference " << worst);
    CHECK(worst < 0.02);
}

TEST_CASE("glTF: KHR_materials_transmission's texture sets the transmitting share per hit",
          "[gltf][mesh-file]") {
    test::TempDir dir;
    write_texture(dir.file("t.png"));
    // Red 1, 0, 0.5, 1 in the four texels (read linearly) times transmissionFactor 1.
    const unsigned char tr[] = {255, 0, 0, 0, 0, 0, 128, 0, 0, 255, 0, 0};
    write_gltf_with_texture(dir, tr, "tr.png", R"("KHR_materials_transmission":
        {"transmissionFactor": 1, "transmissionTexture": {"index": 1}})");
    // Head-on with nothing behind: where a share v transmits, the diffuse base and its
    // reflection keep 1 - v, and the transmitting dielectric reflects as the base's own
    // reflection does (F0 0.04 by GGX of alpha 1: 0.01).
    const double worst = worst_textured_half(
        dir, "tr.png", [](const TextureImage& base, const TextureImage& share, float x, float y) {
            const float v = share.bilinear({x, y}).r;
            return (base.bilinear({x, y}) * 0.96f + RGB{0.01f}) * (1.f - v) + RGB{0.01f * v};
        });
    INFO("worst pixel difference " << worst);
    CHECK(worst < 0.01);
}

TEST_CASE("glTF: KHR_materials_specular's texture sets the reflection's strength per hit",
          "[gltf][mesh-file]") {
    test::TempDir dir;
    write_texture(dir.file("t.png"));
    // Alpha 1, 0, 0.5, 1 (read linearly) times specularFactor 1; the colours are not read.
    const unsigned char sp[] = {9, 9, 9, 255, 9, 9, 9, 0, 9, 9, 9, 128, 9, 9, 9, 255};
    write_gltf_with_texture(dir, sp, "sp.png",
                            R"("KHR_materials_specular": {"specularFactor": 1,
        "specularTexture": {"index": 1}})",
                            4);
    // Head-on: the reflection (F0 0.04 by GGX of alpha 1) gives 0.01 v, the base keeps
    // 1 - 0.04 v.
    const double worst = worst_textured_half(
        dir, "sp.png",
        [](const TextureImage& base, const TextureImage& strength, float x, float y) {
            const float v = strength.bilinear_alpha({x, y});
            return base.bilinear({x, y}) * (1.f - 0.04f * v) + RGB{0.01f * v};
        });
    INFO("worst pixel difference " << worst);
    CHECK(worst < 0.005);
}

TEST_CASE("glTF: textures read their own uv set, two in one material", "[gltf][mesh-file]") {
    test::TempDir dir;
    write_texture(dir.file("t.png"));
    write_gltf(dir);
    // A second uv set for the left primitive, mirrored in u (u' = 0.5 - u), after the
    // buffer's 152 bytes; the base colour texture reads it.
    {
        const float uv1[] = {0.5f, 1, 0, 1, 0, 0, 0.5f, 0};
        std::ofstream(dir.file("quad.bin"), std::ios::binary | std::ios::app)
            .write(reinterpret_cast<const char*>(uv1), sizeof uv1);
        GltfEdit edit(dir.file("quad.gltf"));
        edit(R"("TEXCOORD_0": 2})", R"("TEXCOORD_0": 2, "TEXCOORD_1": 6})");
        edit(R"("baseColorTexture": {"index": 0})",
             R"("baseColorTexture": {"index": 0, "texCoord": 1})");
        edit(R"("byteLength": 152})", R"("byteLength": 184})");
        edit(R"({"buffer": 0, "byteOffset": 128, "byteLength": 24}])",
             R"({"buffer": 0, "byteOffset": 128, "byteLength": 24},
                {"buffer": 0, "byteOffset": 152, "byteLength": 32}])");
        edit(R"("type": "SCALAR"}])", R"("type": "SCALAR"},
            {"bufferView": 3, "byteOffset": 0, "componentType": 5126, "count": 4, "type": "VEC2"}])");
    }
    write_scene(dir.file("s.xml"), R"(<triangle_mesh src="quad.gltf"/>)");
    const Scene s = load_scene(dir.file("s.xml"));
    const TextureImage& img = s.texture_images[0];
    const double worst = worst_pixel(dir.file("s.xml"), [&](float x, float y) {
        return (x < 0.5f ? img.bilinear({0.5f - x, y}) : RGB{0.2f, 0.4f, 0.6f}) * 0.96f +
               RGB{0.01f};
    });
    INFO("worst pixel difference " << worst);
    CHECK(worst < 0.02);
    // Both sets in one material: the base colour on TEXCOORD_1 as above, the transmitting
    // share on TEXCOORD_0: the same image's red read linearly (1, 0, 0, 0.502), the
    // transmitting part reflecting 0.01 head-on (as in the transmission test below).
    {
        GltfEdit edit(dir.file("quad.gltf"));
        edit(R"("baseColorTexture": {"index": 0, "texCoord": 1}, "metallicFactor": 0})",
             R"("baseColorTexture": {"index": 0, "texCoord": 1}, "metallicFactor": 0},
                "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1,
                  "transmissionTexture": {"index": 0, "texCoord": 0}}})");
    }
    const Scene both = load_scene(dir.file("s.xml"));
    REQUIRE(both.texture_images.size() == 2);
    // The base colour's image is the textured material's texture's; the share the other.
    const uint32_t colour_image = both.textures[std::size_t(both.material_of(0).texture)].image;
    const TextureImage& colour = both.texture_images[colour_image];
    const TextureImage& share = both.texture_images[1 - colour_image];
    const double worst_both = worst_pixel(dir.file("s.xml"), [&](float x, float y) {
        if (x >= 0.5f) return RGB{0.2f, 0.4f, 0.6f} * 0.96f + RGB{0.01f};
        const float v = share.bilinear({x, y}).r;
        return (colour.bilinear({0.5f - x, y}) * 0.96f + RGB{0.01f}) * (1.f - v) + RGB{0.01f * v};
    });
    INFO("worst pixel difference, two sets " << worst_both);
    CHECK(worst_both < 0.02);
    {
        const MeshFile f = load_gltf(dir.file("quad.gltf"));
        CHECK(f.parts[0].mesh.uvs2.size() == 8);
        CHECK(f.parts[1].mesh.uvs2.empty());
    }
    // A third set in one material is noted (that texture reads the first).
    {
        GltfEdit edit(dir.file("quad.gltf"));
        edit(R"("transmissionTexture": {"index": 0, "texCoord": 0})",
             R"("transmissionTexture": {"index": 0, "texCoord": 2})");
        edit(R"("metallicFactor": 0},
                "extensions")",
             R"("metallicFactor": 0}, "normalTexture": {"index": 0},
                "extensions")");
    }
    const MeshFile f = load_gltf(dir.file("quad.gltf"));
    bool noted = false;
    for (const std::string& n : f.notes)
        noted |= n.find("transmissionTexture uses TEXCOORD_2, a third uv set in one material") !=
                 std::string::npos;
    CHECK(noted);
}

TEST_CASE("glTF: KHR_materials_specular weights and tints the dielectric reflection",
          "[gltf][mesh-file]") {
    test::TempDir dir;
    write_texture(dir.file("t.png"));
    SECTION("specularFactor 0: a Lambert of the base colour, nothing taken for a reflection") {
        write_gltf(dir, R"(, "extensions": {"KHR_materials_specular": {"specularFactor": 0}})");
        write_scene(dir.file("s.xml"), R"(<triangle_mesh src="quad.gltf"/>)");
        const Scene s = load_scene(dir.file("s.xml"));
        const TextureImage& img = s.texture_images[0];
        const double worst = worst_pixel(dir.file("s.xml"), [&](float x, float y) {
            return x < 0.5f ? img.bilinear({x, y}) * 0.96f + RGB{0.01f} : RGB{0.2f, 0.4f, 0.6f};
        });
        INFO("worst pixel difference " << worst);
        CHECK(worst < 0.02);
    }
    SECTION("half strength and a tint: Schlick from F0 = 0.04 x tint, the diffuse keeps the rest") {
        write_gltf(dir, R"(, "extensions": {"KHR_materials_specular":
            {"specularFactor": 0.5, "specularColorFactor": [2, 1, 0.5]}})");
        write_scene(dir.file("s.xml"), R"(<triangle_mesh src="quad.gltf"/>)");
        const Scene s = load_scene(dir.file("s.xml"));
        const TextureImage& img = s.texture_images[0];
        // Head-on, alpha 1: the reflection is weight x F0 / 4 = (0.01, 0.005, 0.0025); the
        // Lambert keeps 1 - 0.5 x max(F0) = 0.96 of the colour.
        const double worst = worst_pixel(dir.file("s.xml"), [&](float x, float y) {
            return x < 0.5f ? img.bilinear({x, y}) * 0.96f + RGB{0.01f}
                            : RGB{0.2f, 0.4f, 0.6f} * 0.96f + RGB{0.01f, 0.005f, 0.0025f};
        });
        INFO("worst pixel difference " << worst);
        CHECK(worst < 0.003);
    }
    SECTION("out-of-range factors are errors naming the material") {
        write_gltf(dir, R"(, "extensions": {"KHR_materials_specular": {"specularFactor": 2}})");
        CHECK_THROWS_WITH(load_gltf(dir.file("quad.gltf")),
                          Catch::Contains("specularFactor must be in [0, 1]"));
    }
}

TEST_CASE("glTF: KHR_materials_clearcoat adds a clear GGX coat over the material",
          "[gltf][mesh-file]") {
    test::TempDir dir;
    write_texture(dir.file("t.png"));
    write_gltf(dir, R"(, "extensions": {"KHR_materials_clearcoat":
        {"clearcoatFactor": 1, "clearcoatRoughnessFactor": 1, "clearcoatNormalTexture": {"index": 0}}})");
    write_scene(dir.file("s.xml"), R"(<triangle_mesh src="quad.gltf"/>)");
    const Scene s = load_scene(dir.file("s.xml"));
    const TextureImage& img = s.texture_images[0];
    // The extension is on the right primitive's material. Head-on under irradiance pi: the coat
    // reflects F0 = 0.04 by GGX of alpha 1 (0.01, as the material's own dielectric reflection
    // does), and everything under it keeps 1 - 0.04.
    const double worst = worst_pixel(dir.file("s.xml"), [&](float x, float y) {
        if (x < 0.5f) return img.bilinear({x, y}) * 0.96f + RGB{0.01f};
        return (RGB{0.2f, 0.4f, 0.6f} * 0.96f + RGB{0.01f}) * 0.96f + RGB{0.01f};
    });
    INFO("worst pixel difference " << worst);
    CHECK(worst < 0.003);
    // Its normal texture is noted: the material's shading normal stands for it.
    bool noted = false;
    for (const std::string& w : s.warnings)
        noted |= w.find("clearcoatNormalTexture ignored") != std::string::npos;
    CHECK(noted);
    write_gltf(dir, R"(, "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1.5}})");
    CHECK_THROWS_WITH(load_gltf(dir.file("quad.gltf")),
                      Catch::Contains("clearcoatFactor must be in [0, 1]"));
    write_gltf(dir, R"(, "extensions": {"KHR_materials_clearcoat":
        {"clearcoatFactor": 1, "clearcoatTexture": {"index": 7}}})");
    CHECK_THROWS_WITH(load_gltf(dir.file("quad.gltf")),
                      Catch::Contains("texture 7 does not exist"));
}

TEST_CASE("glTF: KHR_materials_clearcoat's textures set the coat per hit", "[gltf][mesh-file]") {
    test::TempDir dir;
    write_texture(dir.file("t.png"));
    // The coat's texture, 2 x 2 and read linearly: red is the coat's strength (times its
    // factor), green the coat's roughness (times its factor): (1, 1), (0, 0.5), (0.5, 1),
    // (1, 0.5).
    const unsigned char cc[] = {255, 255, 0, 0, 128, 0, 128, 255, 0, 255, 128, 0};
    write_gltf_with_texture(dir, cc, "cc.png", R"("KHR_materials_clearcoat": {"clearcoatFactor": 1,
        "clearcoatRoughnessFactor": 1, "clearcoatTexture": {"index": 1},
        "clearcoatRoughnessTexture": {"index": 1}})");
    write_scene(dir.file("s.xml"), R"(<triangle_mesh src="quad.gltf"/>)");
    const Scene s = load_scene(dir.file("s.xml"));
    REQUIRE(s.texture_images.size() == 2);
    const TextureImage& base = s.texture_images[0];
    const TextureImage& coat = s.texture_images[1];
    // Head-on under irradiance pi: the base (0.96 of the colour plus the material's own
    // dielectric reflection, 0.01) keeps 1 - 0.04 c under a coat of strength c, which reflects
    // c F0 D(n) / 4 pi = 0.01 c / alpha^2 (GGX, alpha = green^2, its G 1 head-on).
    const double worst = worst_pixel(dir.file("s.xml"), [&](float x, float y) {
        if (x >= 0.5f) return RGB{0.2f, 0.4f, 0.6f} * 0.96f + RGB{0.01f};
        const RGB t = coat.bilinear({x, y});
        const float c = t.r, alpha = std::max(t.g * t.g, 1e-3f);
        return (base.bilinear({x, y}) * 0.96f + RGB{0.01f}) * (1.f - 0.04f * c) +
               RGB{0.01f * c / (alpha * alpha)};
    });
    INFO("worst pixel difference " << worst);
    CHECK(worst < 0.01);
}

TEST_CASE("glTF and MTL: normal maps are read linearly and set the material's map",
          "[gltf][obj][normal_map][mesh-file][fast]") {
    test::TempDir dir;
    write_texture(dir.file("t.png"));
    write_gltf(dir, R"(, "normalTexture": {"index": 0})");
    const MeshFile f = load_gltf(dir.file("quad.gltf"));
    REQUIRE(f.materials.size() == 2);
    CHECK(f.materials[0].normal_map.empty());
    REQUIRE(!f.materials[1].normal_map.empty());
    Scene s;
    std::map<std::string, uint32_t> images;
    const Material tex = s.materials[add_file_material(s, f.materials[0], f, images)];
    const Material flat = s.materials[add_file_material(s, f.materials[1], f, images)];
    CHECK(tex.normal_map < 0);
    REQUIRE(flat.normal_map >= 0);
    // The same PNG as colour (sRGB-decoded) and as a normal map (linear): two images.
    REQUIRE(s.texture_images.size() == 2);
    const TextureImage& colour = s.texture_images[s.textures[std::size_t(tex.texture)].image];
    const TextureImage& normal = s.texture_images[s.textures[std::size_t(flat.normal_map)].image];
    REQUIRE(colour.texels.size() == normal.texels.size());
    for (std::size_t i = 0; i < colour.texels.size(); ++i)
        CHECK(colour.texels[i].g == Approx(srgb_to_linear(normal.texels[i].g)).margin(1e-5));
    // MTL's norm (the PBR extension's normal map).
    std::vector<std::string> notes;
    const auto m =
        parse_mtl("newmtl n\nKd 0.5 0.5 0.5\nnorm t.png\n", "n.mtl", dir.path().string(), notes);
    CHECK(m.at("n").normal_map == dir.file("t.png"));
    const Material mtl = s.materials[add_file_material(s, m.at("n"), MeshFile{}, images)];
    CHECK(mtl.normal_map >= 0);
}

TEST_CASE("MTL: map_Bump is a height map or a normal map, told by its texels",
          "[obj][normal_map][mesh-file]") {
    test::TempDir dir;
    // A 64 x 4 grey ramp, 0 to 252 in steps of 4 along u: heights 0 to ~1 across the unit
    // quad, a slope of 1.004 (-bm 1); a bluish normal map; a red image, neither.
    auto write = [&](const std::string& name, auto&& texel) {
        std::vector<unsigned char> px;
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 64; ++x) {
                const std::array<unsigned char, 3> c = texel(x);
                px.insert(px.end(), c.begin(), c.end());
            }
        REQUIRE(stbi_write_png(dir.file(name).c_str(), 64, 4, 3, px.data(), 64 * 3) != 0);
    };
    write("ramp.png", [](int x) {
        const auto v = static_cast<unsigned char>(4 * x);
        return std::array<unsigned char, 3>{v, v, v};
    });
    write("normal.png", [](int) { return std::array<unsigned char, 3>{128, 128, 255}; });
    write("red.png", [](int) { return std::array<unsigned char, 3>{200, 30, 30}; });
    std::ofstream(dir.file("quad.mtl"))
        << "newmtl ramp\nKd 1 1 1\nmap_Bump -bm 1 ramp.png\n"
        << "newmtl normal\nKd 1 1 1\nbump normal.png\n"
        << "newmtl both\nKd 1 1 1\nnorm normal.png\nmap_Bump normal.png\n"
        << "newmtl red\nKd 1 1 1\nmap_Bump red.png\n";
    std::vector<std::string> notes;
    std::ifstream in(dir.file("quad.mtl"));
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto mtl = parse_mtl(text, "quad.mtl", dir.path().string(), notes);
    CHECK(mtl.at("ramp").bump_multiplier == 1.f);
    CHECK(std::find_if(notes.begin(), notes.end(), [](const std::string& n) {
              return n.find("'both': norm is its normal map") != std::string::npos;
          }) != notes.end());
    Scene s;
    std::map<std::string, uint32_t> images;
    const Material ramp = s.materials[add_file_material(s, mtl.at("ramp"), MeshFile{}, images)];
    CHECK(ramp.bump >= 0);
    CHECK(ramp.normal_map < 0);
    const Material normal = s.materials[add_file_material(s, mtl.at("normal"), MeshFile{}, images)];
    CHECK(normal.bump < 0);
    CHECK(normal.normal_map >= 0);
    CHECK(s.materials[add_file_material(s, mtl.at("both"), MeshFile{}, images)].normal_map >= 0);
    CHECK_THROWS_WITH(add_file_material(s, mtl.at("red"), MeshFile{}, images),
                      Catch::Contains("red.png") && Catch::Contains("'red'") &&
                          Catch::Contains("neither a height map"));
    CHECK_THROWS_WITH(parse_mtl("newmtl a\nmap_Bump -clamp on x.png\n", "a.mtl", ".", notes),
                      Catch::Contains("a.mtl:2") && Catch::Contains("-bm is"));
    // Rendered: the ramp's slope 1.004 tilts the normal by 45 degrees along u, so a white
    // Lambertian lit head-on shows 1 / sqrt(1 + 1.004^2) = 0.7057 (away from the ramp's
    // wrap-around at u = 0 and 1, where the repeating image jumps from 252 to 0).
    std::ofstream(dir.file("quad.obj")) << "mtllib quad.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                           "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
                                           "usemtl ramp\nf 1/1/1 2/2/1 3/3/1 4/4/1\n";
    write_scene(dir.file("s.xml"), R"(<triangle_mesh src="quad.obj"/>)");
    TestScene ts(load_scene(dir.file("s.xml")));
    const auto acc = make_intersector(ts, ts.accel);
    RenderOptions opt = ts.render.run;
    opt.spp = 4;
    const Film f = render(ts, ts.render, *acc, opt).film;
    double sum = 0.0;
    int n = 0;
    for (int y = 8; y < 56; ++y)
        for (int x = 8; x < 56; ++x, ++n) sum += f.pixels[std::size_t(y) * 64 + std::size_t(x)].g;
    CHECK(sum / n == Approx(1.0 / std::sqrt(1.0 + 1.004 * 1.004)).epsilon(0.01));
}

TEST_CASE("glTF: KHR_lights_punctual lights are placed by their nodes and the object",
          "[gltf][mesh-file][fast]") {
    test::TempDir dir;
    write_texture(dir.file("t.png"));
    write_gltf(dir);
    {
        // Three lights on three more root nodes: a point light at (0, 2, 0), a spot light at
        // (1, 1, 1) turned to shine along -y, and a directional light shining along -z.
        GltfEdit replace(dir.file("quad.gltf"));
        replace(R"("scenes": [{"nodes": [0]}])", R"("scenes": [{"nodes": [0, 2, 3, 4]}])");
        replace(R"({"scale": [0.5, 1, 1], "mesh": 0})", R"({"scale": [0.5, 1, 1], "mesh": 0},
            {"translation": [0, 2, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"translation": [1, 1, 1], "rotation": [-0.7071068, 0, 0, 0.7071068],
             "extensions": {"KHR_lights_punctual": {"light": 1}}},
            {"extensions": {"KHR_lights_punctual": {"light": 2}}})");
        replace(R"("asset")", R"("extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {"KHR_lights_punctual": {"lights": [
    {"type": "point", "color": [1, 0.5, 0.25], "intensity": 683},
    {"type": "spot", "intensity": 1366, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}},
    {"type": "directional", "intensity": 68.3}]}},
  "asset")");
    }
    write_scene(dir.file("s.xml"), R"(<triangle_mesh src="quad.gltf">
        <transform><translate x="10" y="0" z="0"/></transform></triangle_mesh>)");
    const Scene s = load_scene(dir.file("s.xml"));
    REQUIRE(s.lights.points.size() == 1);
    REQUIRE(s.lights.spots.size() == 1);
    REQUIRE(s.lights.directionals.size() == 2);  // the scene's own, then the file's
    // Photometric over 683 lm/W; the object's translation moves the lights too.
    CHECK(s.lights.points[0].intensity.g == Approx(0.5f));
    CHECK(s.lights.points[0].position.x == Approx(10.f));
    CHECK(s.lights.points[0].position.y == Approx(2.f));
    const SpotLight& spot = s.lights.spots[0];
    CHECK(spot.intensity.r == Approx(2.f));
    CHECK(spot.position.x == Approx(11.f));
    CHECK(spot.direction.y == Approx(-1.f).margin(1e-5));
    CHECK(spot.cos_outer == Approx(std::cos(0.5f)));
    CHECK(spot.cos_inner == Approx(std::cos(0.2f)));
    CHECK(s.lights.directionals[1].direction.z == Approx(-1.f));
    CHECK(s.lights.directionals[1].radiance.b == Approx(0.1f));
}

TEST_CASE(
    "glTF: the first perspective camera is the file's view, transmission and ior a "
    "dielectric",
    "[gltf][mesh-file][fast]") {
    test::TempDir dir;
    write_texture(dir.file("t.png"));
    write_gltf(dir, R"(, "extensions": {"KHR_materials_transmission": {"transmissionFactor": 0.75},
        "KHR_materials_ior": {"ior": 1.33}})");
    {
        GltfEdit replace(dir.file("quad.gltf"));
        // A camera at (0.5, 0.5, 3) looking down -z, 30 degrees vertically.
        replace(R"("scenes": [{"nodes": [0]}])", R"("scenes": [{"nodes": [0, 2]}])");
        replace(
            R"({"scale": [0.5, 1, 1], "mesh": 0})",
            R"({"scale": [0.5, 1, 1], "mesh": 0}, {"translation": [0.5, 0.5, 3], "camera": 0})");
        replace(R"("asset")", R"("cameras": [{"type": "perspective",
            "perspective": {"yfov": 0.5235988, "aspectRatio": 2, "znear": 0.01}}], "asset")");
    }
    const MeshFile f = load_gltf(dir.file("quad.gltf"));
    REQUIRE(f.view);
    CHECK(f.view->eye.z == Approx(3.f));
    CHECK(f.view->target.z == Approx(2.f));
    CHECK(f.view->vertical_fov_degrees == Approx(30.f));
    // Rendered directly, the file's camera is the scene's.
    const Scene s = load_scene(dir.file("quad.gltf"));
    CHECK(s.camera.eye.x == Approx(0.5f));
    CHECK(s.camera.eye.z == Approx(3.f));
    CHECK(s.camera.vertical_fov_degrees() == Approx(30.f).epsilon(1e-3));
    // At the file's aspect ratio; another size (--width, --height) keeps the vertical field
    // of view the file gives (a scene's own camera keeps its horizontal one).
    CHECK(s.film.width == 640);
    CHECK(s.film.height == 320);
    Scene resized = load_scene(dir.file("quad.gltf"));
    resized.set_resolution(300, 100);
    CHECK(resized.camera.vertical_fov_degrees() == Approx(30.f).epsilon(1e-3));
    // The flat material: 0.25 of its base colour diffuse (less the reflection's F0 of 1.33,
    // 0.0201) beside that share's GGX reflection, a dielectric of 1.33 for the rest.
    REQUIRE(f.materials[1].transmission == Approx(0.75f));
    Scene t;
    std::map<std::string, uint32_t> images;
    const Material m = t.materials[add_file_material(t, f.materials[1], f, images)];
    REQUIRE(m.bsdf.size() == 3);
    CHECK(m.bsdf.lobe(0).color.b == Approx(0.6f * 0.25f * (1.f - 0.0201f)).epsilon(1e-3));
    CHECK(m.bsdf.lobe(1).type == LobeType::Microfacet);
    CHECK(m.bsdf.lobe(1).color.g == Approx(0.25f));
    CHECK(m.bsdf.lobe(1).fresnel.kind == FresnelKind::Dielectric);
    CHECK(m.bsdf.lobe(2).type == LobeType::RoughDielectric);  // roughnessFactor 1: alpha 1
    CHECK(m.bsdf.lobe(2).fresnel.ior == Approx(1.33f));
    CHECK(m.bsdf.lobe(2).transmit.g == Approx(0.4f * 0.75f));
}

TEST_CASE("glTF: metallic-roughness and emission become lobes and emission",
          "[gltf][mesh-file][fast]") {
    test::TempDir dir;
    write_texture(dir.file("t.png"));
    write_gltf(dir, R"(}, {"name": "gold", "emissiveFactor": [1, 0.5, 0.25],
      "pbrMetallicRoughness": {"baseColorFactor": [1, 0.8, 0.3, 1], "metallicFactor": 1, "roughnessFactor": 0.5})");
    // Point the second primitive at the third material.
    {
        std::ifstream in(dir.file("quad.gltf"));
        std::string t((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        t.replace(t.find("\"material\": 1"), 13, "\"material\": 2");
        std::ofstream(dir.file("quad.gltf")) << t;
    }
    const MeshFile f = load_gltf(dir.file("quad.gltf"));
    REQUIRE(f.parts.size() == 2);
    REQUIRE(f.materials.size() == 2);
    Scene s;
    std::map<std::string, uint32_t> images;
    const Material gold = s.materials[add_file_material(s, f.materials[1], f, images)];
    CHECK(gold.emission.g == Approx(0.5f));
    REQUIRE(gold.bsdf.size() == 2);
    CHECK(gold.bsdf.lobe(0).color.r == 0.f);  // no diffuse part in a metal
    CHECK(gold.bsdf.lobe(1).type == LobeType::Microfacet);
}

TEST_CASE("glTF: a metallic-roughness texture weights and roughens the lobes per hit",
          "[gltf][mesh-file][fast]") {
    test::TempDir dir;
    // t.png's texels (linear): red (1, 0, 0), green (0, 1, 0), blue (0, 0, 1), grey 128.
    write_texture(dir.file("t.png"));
    write_gltf(dir, R"(, "emissiveFactor": [2, 2, 2], "emissiveTexture": {"index": 0})");
    {
        GltfEdit replace(dir.file("quad.gltf"));
        replace(R"("baseColorFactor": [0.2, 0.4, 0.6, 1], "metallicFactor": 0})",
                R"("baseColorFactor": [0.2, 0.4, 0.6, 1], "metallicFactor": 0.8,
                   "roughnessFactor": 0.5, "metallicRoughnessTexture": {"index": 0}})");
    }
    const MeshFile f = load_gltf(dir.file("quad.gltf"));
    Scene s;
    std::map<std::string, uint32_t> images;
    const Material m = s.materials[add_file_material(s, f.materials[1], f, images)];
    // Lambert, dielectric reflection, metal: weighted per hit by the blue channel (metallic).
    REQUIRE(m.bsdf.size() == 3);
    CHECK(m.num_float_params == 5);
    CHECK(m.emission_texture >= 0);
    std::optional<Material> scratch;
    // The texel centres of the 2 x 2 image: (0.25, 0.75) red, (0.75, 0.75) green,
    // (0.25, 0.25) blue (foton's v runs up).
    const Material& blue = s.material_at(m, {0.25f, 0.25f}, scratch);
    // metallic = 0.8 x 1: the Lambert keeps 0.2 of 0.96 of its colour, the metal 0.8;
    // roughness = 0.5 x 0: alpha at its floor, 1e-3.
    CHECK(blue.bsdf.lobe(0).color.b == Approx(0.6f * 0.96f * 0.2f).epsilon(1e-3));
    CHECK(blue.bsdf.lobe(2).color.g == Approx(0.8f).epsilon(1e-3));
    CHECK(blue.bsdf.lobe(2).dist.alpha == Approx(1e-3f));
    // Emission: 2 x the texel (sRGB-decoded, blue).
    CHECK(blue.emission.b == Approx(2.f).epsilon(1e-3));
    CHECK(blue.emission.r == Approx(0.f).margin(1e-4));
    std::optional<Material> scratch2;
    const Material& green = s.material_at(m, {0.75f, 0.75f}, scratch2);
    // metallic 0, roughness 0.5 x 1: alpha 0.25 on the reflection and the metal.
    CHECK(green.bsdf.lobe(0).color.b == Approx(0.6f * 0.96f).epsilon(1e-3));
    CHECK(green.bsdf.lobe(1).color.g == Approx(1.f).epsilon(1e-3));
    CHECK(green.bsdf.lobe(1).dist.alpha == Approx(0.25f).epsilon(1e-3));
    CHECK(green.bsdf.lobe(2).color.g == Approx(0.f).margin(1e-5));
}

TEST_CASE("mesh files: bad input names the file and line or glTF object",
          "[mesh-file][bad-input]") {
    test::TempDir dir;
    write_texture(dir.file("t.png"));
    auto error_of = [&](const std::string& mesh_xml) -> std::string {
        write_scene(dir.file("s.xml"), mesh_xml);
        try {
            load_scene(dir.file("s.xml"));
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    std::ofstream(dir.file("a.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nmtllib none.mtl\nf 1 2 3\n";
    CHECK_THAT(error_of(R"(<triangle_mesh src="a.obj"/>)"),
               Catch::Contains("a.obj:4: mtllib 'none.mtl': file not found"));
    std::ofstream(dir.file("m.mtl")) << "newmtl x\nKd 0.5 0.5 0.5\nmap_Kd missing.png\n";
    std::ofstream(dir.file("b.obj"))
        << "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl y\nf 1 2 3\n";
    CHECK_THAT(error_of(R"(<triangle_mesh src="b.obj"/>)"),
               Catch::Contains("b.obj:5: usemtl 'y': no such material"));
    std::ofstream(dir.file("c.obj"))
        << "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n";
    CHECK_THAT(error_of(R"(<triangle_mesh src="c.obj"/>)"), Catch::Contains("missing.png"));
    // A texture that is not an image.
    std::ofstream(dir.file("n.mtl")) << "newmtl x\nmap_Kd m.mtl\n";
    std::ofstream(dir.file("d.obj"))
        << "mtllib n.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n";
    CHECK_THAT(error_of(R"(<triangle_mesh src="d.obj"/>)"),
               Catch::Contains("not a readable image"));
    std::ofstream(dir.file("e.stl")) << "solid\n";
    CHECK_THAT(error_of(R"(<triangle_mesh src="e.stl"/>)"),
               Catch::Contains("s.xml:3: ") && Catch::Contains("unknown mesh format '.stl'"));
    // glTF: malformed JSON, an accessor past its buffer, an index past its vertices.
    std::ofstream(dir.file("f.gltf")) << "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [";
    CHECK_THAT(error_of(R"(<triangle_mesh src="f.gltf"/>)"), Catch::Contains("malformed glTF"));
    write_gltf(dir);
    auto edit = [&](const std::string& from, const std::string& to) {
        std::ifstream in(dir.file("quad.gltf"));
        std::string t((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        REQUIRE(t.find(from) != std::string::npos);
        t.replace(t.find(from), from.size(), to);
        std::ofstream(dir.file("g.gltf")) << t;
    };
    edit(R"("count": 4, "type": "VEC3"},)", R"("count": 40, "type": "VEC3"},)");
    CHECK_THAT(
        error_of(R"(<triangle_mesh src="g.gltf"/>)"),
        Catch::Contains("mesh 0 primitive 0 POSITION, accessor 0: reads beyond its bufferView"));
    std::ofstream(dir.file("quad.bin"), std::ios::binary | std::ios::in | std::ios::out)
        .seekp(128)
        .write("\x09\x00", 2);
    CHECK_THAT(error_of(R"(<triangle_mesh src="quad.gltf"/>)"),
               Catch::Contains("mesh 0 primitive 0: index 9 outside its 4 vertices"));
}

TEST_CASE("XML textures: an image and a checkerboard on diffuse reflectances",
          "[xml][texture][mesh-file]") {
    test::TempDir dir;
    write_texture(dir.file("t.png"));
    // The left half a PLY quad with uv under a textured Lambert; the right half a quad under
    // a checkerboard matte, scaled to 4 x 4 cells.
    std::ofstream(dir.file("left.ply"))
        << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
           "property float z\nproperty float u\nproperty float v\nelement face 1\n"
           "property list uchar int vertex_indices\nend_header\n"
           "0 0 0 0 0\n0.5 0 0 0.5 0\n0.5 1 0 0.5 1\n0 1 0 0 1\n4 0 1 2 3\n";
    write_scene(dir.file("s.xml"), R"(<triangle_mesh src="left.ply">
        <material type="lambert"><texture src="t.png"/></material></triangle_mesh>
      <triangle_mesh src="left.ply"><transform><translate x="0.5" y="0" z="0"/></transform>
        <material type="lambert"><reflectance r="1" g="1" b="1"/>
          <texture type="checkerboard" scale_u="8" scale_v="4"><even r="0.9" g="0.8" b="0.7"/>
            <odd r="0.1" g="0.2" b="0.3"/></texture></material></triangle_mesh>)");
    const Scene s = load_scene(dir.file("s.xml"));
    REQUIRE(s.textures.size() == 2);
    const TextureImage& img = s.texture_images[0];
    const double worst = worst_pixel(dir.file("s.xml"), [&](float x, float y) {
        if (x < 0.5f) return img.bilinear({x, y});
        // uv of the right quad: (x - 0.5, y); 8 x 4 cells over it.
        const bool even = (int(std::floor((x - 0.5f) * 8.f)) + int(std::floor(y * 4.f))) % 2 == 0;
        return even ? RGB{0.9f, 0.8f, 0.7f} : RGB{0.1f, 0.2f, 0.3f};
    });
    INFO("worst pixel difference " << worst);
    CHECK(worst < 0.02);
    // Bad input at its line.
    auto error_of = [&](const std::string& material) -> std::string {
        write_scene(dir.file("b.xml"),
                    R"(<sphere radius="1"><center x="0" y="0" z="0"/>)" + material + "</sphere>");
        try {
            load_scene(dir.file("b.xml"));
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    CHECK_THAT(error_of(R"(<material type="lambert"><texture src="none.png"/></material>)"),
               Catch::Contains("b.xml:3: texture 'none.png'"));
    CHECK_THAT(error_of(R"(<material type="conductor"><texture src="t.png"/></material>)"),
               Catch::Contains("multiplies a diffuse reflectance"));
    CHECK_THAT(error_of(R"(<material type="lambert"><texture type="wood"/></material>)"),
               Catch::Contains("unknown texture type 'wood'"));
    CHECK_THAT(error_of(R"(<material type="mix">
        <material type="lambert" weight="0.5"><texture src="t.png"/></material>
        <material type="lambert" weight="0.5"><texture src="t.png"/></material></material>)"),
               Catch::Contains("a mix takes one textured component"));
}

TEST_CASE("glTF and MTL: alphaMode and dissolve cut the surface out as the file says",
          "[gltf][obj][alpha][mesh-file][fast]") {
    test::TempDir dir;
    // RGBA texels (alpha 0, 1 / 100/255, 1) for the textured half under MASK, cutoff 0.3; its
    // uv is the plane's (x, y), so it shows the left column (alpha 0 and 0.39) at u = 0.25.
    const unsigned char px[] = {255, 0, 0, 0, 0, 255, 0, 255, 0, 0, 255, 100, 128, 128, 128, 255};
    REQUIRE(stbi_write_png(dir.file("t.png").c_str(), 2, 2, 4, px, 8) != 0);
    write_gltf(dir, R"(, "alphaMode": "BLEND")");
    {
        GltfEdit edit(dir.file("quad.gltf"));
        edit("[0.2, 0.4, 0.6, 1]", "[0.2, 0.4, 0.6, 0.25]");
        edit(R"("name": "tex", )", R"("name": "tex", "alphaMode": "MASK", "alphaCutoff": 0.3, )");
    }
    write_scene(dir.file("s.xml"), R"(<triangle_mesh src="quad.gltf"/>)");
    TestScene s(load_scene(dir.file("s.xml")));
    const Material& tex = material_of_part(s, 0);
    const Material& flat = material_of_part(s, 1);
    CHECK(tex.alpha_texture >= 0);
    CHECK(tex.alpha_cutoff == Approx(0.3f));
    CHECK(flat.alpha == Approx(0.25f));
    CHECK(flat.alpha_texture < 0);
    CHECK(flat.alpha_cutoff < 0.f);
    // Rays straight down: at the textured half's texel centres the mask cuts alpha 0 and keeps
    // 0.39 (above the cutoff); the BLEND half stops a quarter of many rays.
    const auto acc = make_intersector(s, AccelType::Bvh);
    auto hits = [&](float x, float y) {
        RayBatch r;
        r.push({x, y, 1.f}, {0.f, 0.f, -1.f}, 0.f, kInfinity, 0);
        HitBatch h;
        TraceCounters c;
        acc->intersect(r, h, c);
        return h.geom[0] != kNoHit;
    };
    CHECK(hits(0.25f, 0.25f) != hits(0.25f, 0.75f));
    CHECK(tex.alpha_texture >= 0);
    const Texture& mask = s.textures[std::size_t(tex.alpha_texture)];
    for (const float v : {0.25f, 0.75f}) {
        const float a = mask.eval_float(s.texture_images, {0.25f, v});
        CHECK((std::fabs(a) < 1e-6f || std::fabs(a - 100.f / 255.f) < 1e-6f));
        CHECK(hits(0.25f, v) == (a >= 0.3f));
    }
    int stopped = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i)
        stopped +=
            hits(0.5f + 0.5f * (float(i % 200) + 0.5f) / 200.f, (float(i / 200) + 0.5f) / 100.f)
                ? 1
                : 0;
    INFO("BLEND stopped " << stopped << " of " << n);
    CHECK(std::fabs(double(stopped) / n - 0.25) < 0.02);
    // OPAQUE ignores the alpha; an unknown mode is an error naming the material.
    {
        GltfEdit edit(dir.file("quad.gltf"));
        edit(R"("alphaMode": "BLEND")", R"("alphaMode": "OPAQUE")");
    }
    CHECK(!load_scene(dir.file("s.xml")).material_of(1).cuts_out());
    {
        GltfEdit edit(dir.file("quad.gltf"));
        edit(R"("alphaMode": "OPAQUE")", R"("alphaMode": "CLIP")");
    }
    CHECK_THROWS_WITH(load_gltf(dir.file("quad.gltf")),
                      Catch::Contains("material 1") && Catch::Contains("alphaMode 'CLIP'"));
    // MTL: d and Tr are coverage, map_d a float image; glass ignores its dissolve.
    std::vector<std::string> notes;
    const auto m = parse_mtl(
        "newmtl a\nKd 0.5 0.5 0.5\nd 0.4\nnewmtl b\nKd 0.5 0.5 0.5\nTr 0.25\nmap_d t.png\n"
        "newmtl g\nillum 7\nd 0.5\n",
        "m.mtl", dir.path().string(), notes);
    CHECK(m.at("a").alpha == Approx(0.4f));
    CHECK(m.at("b").alpha == Approx(0.75f));
    CHECK(m.at("b").alpha_map == dir.file("t.png"));
    CHECK(m.at("g").alpha == 1.f);
    Scene sm;
    std::map<std::string, uint32_t> images;
    const Material b = sm.materials[add_file_material(sm, m.at("b"), MeshFile{}, images)];
    REQUIRE(b.alpha_texture >= 0);
    CHECK(b.alpha == Approx(0.75f));
    CHECK(!sm.materials[add_file_material(sm, m.at("g"), MeshFile{}, images)].cuts_out());
    CHECK_THROWS_WITH(parse_mtl("newmtl a\nd 1.5\n", "m.mtl", ".", notes),
                      Catch::Contains("m.mtl:2: d must be in [0, 1]"));
}

TEST_CASE("glTF: KHR_texture_transform moves, turns and scales a texture as the spec says",
          "[gltf][texture][mesh-file]") {
    test::TempDir dir;
    write_texture(dir.file("t.png"));
    write_gltf(dir);
    {
        GltfEdit edit(dir.file("quad.gltf"));
        edit(R"("baseColorTexture": {"index": 0})",
             R"("baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform":
                {"offset": [0.25, 0.1], "rotation": 0.5, "scale": [2, 1.5]}}})");
    }
    write_scene(dir.file("s.xml"), R"(<triangle_mesh src="quad.gltf"/>)");
    const Scene s = load_scene(dir.file("s.xml"));
    const TextureImage& img = s.texture_images[0];
    // The spec's uv' = T R S uv with R = [cos sin; -sin cos], in glTF's uv (v down): the left
    // primitive's glTF uv at (x, y) is (x, 1 - y); the image is read at glTF's uv'.
    const float c = std::cos(0.5f), sn = std::sin(0.5f);
    const double worst = worst_pixel(dir.file("s.xml"), [&](float x, float y) {
        if (x >= 0.5f) return RGB{0.2f, 0.4f, 0.6f} * 0.96f + RGB{0.01f};
        const float gx = 2.f * x, gy = 1.5f * (1.f - y);
        const float u = c * gx + sn * gy + 0.25f, v = -sn * gx + c * gy + 0.1f;
        return img.bilinear({u, 1.f - v}) * 0.96f + RGB{0.01f};
    });
    INFO("worst pixel difference " << worst);
    CHECK(worst < 0.03);
    // Without the extension the same file renders the plain texture (checked above); a bad
    // transform is an error naming the material.
    {
        GltfEdit edit(dir.file("quad.gltf"));
        edit(R"("scale": [2, 1.5])", R"("scale": [2])");
    }
    CHECK_THROWS_WITH(
        load_gltf(dir.file("quad.gltf")),
        Catch::Contains("material 0") && Catch::Contains("scale must be two numbers"));
}
