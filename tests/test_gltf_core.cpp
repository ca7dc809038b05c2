// glTF 2.0's core beyond the basic triangle list: vertex colours (COLOR_0) multiplying the
// base colour, triangle strips and fans, sparse accessors, the normal texture's scale and
// orthographic cameras, each checked against what the specification says the file means.
#include <stb/stb_image_write.h>

#include <catch2/catch.hpp>
#include <cstring>
#include <fstream>

#include "engine/core/error.h"
#include "engine/scene/gltf_scene_parts.h"
#include "engine/scene/mesh_file.h"
#include "engine/scene/model_scene.h"
#include "engine/transport/common/shading_normal.h"
#include "engine/transport/common/surface.h"
#include "flat_quad_scene.h"
#include "test_util.h"

using namespace foton;

namespace {

// A glTF file's binary buffer built view by view: each add() appends its bytes (4-aligned)
// as a new bufferView and returns the view's index.
class GltfBuffer {
  public:
    template <class T>
    int add(const std::vector<T>& v) {
        while (bytes_.size() % 4) bytes_.push_back('\0');
        const std::size_t at = bytes_.size();
        bytes_.resize(at + v.size() * sizeof(T));
        std::memcpy(&bytes_[at], v.data(), v.size() * sizeof(T));
        views_.push_back("{\"buffer\": 0, \"byteOffset\": " + std::to_string(at) +
                         ", \"byteLength\": " + std::to_string(v.size() * sizeof(T)) + "}");
        return int(views_.size() - 1);
    }
    // Writes `name`.gltf (and its .bin): `body` holds the other top-level members.
    void write(const test::TempDir& dir, const std::string& name, const std::string& body) const {
        std::ofstream(dir.file(name + ".bin"), std::ios::binary) << bytes_;
        std::string views;
        for (const std::string& v : views_) views += (views.empty() ? "" : ", ") + v;
        std::ofstream(dir.file(name + ".gltf"))
            << "{\"asset\": {\"version\": \"2.0\"}, \"buffers\": [{\"uri\": \"" << name
            << ".bin\", \"byteLength\": " << bytes_.size() << "}], \"bufferViews\": [" << views
            << "], " << body << "}";
    }

  private:
    std::string bytes_;
    std::vector<std::string> views_;
};

// The unit square's corners (0, 0), (1, 0), (1, 1), (0, 1) at z = 0.
const std::vector<float> kQuad = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};

std::string accessor(int view, int type, int count, const char* kind,
                     const std::string& more = "") {
    return "{\"bufferView\": " + std::to_string(view) +
           ", \"componentType\": " + std::to_string(type) +
           ", \"count\": " + std::to_string(count) + ", \"type\": \"" + kind + "\"" + more + "}";
}

// One mesh of one primitive (`primitive`: its members) at the root node, and `more` members.
std::string one_mesh(const std::string& primitive, const std::string& accessors,
                     const std::string& more = "") {
    return R"("scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{)" +
           primitive + R"(}]}], "accessors": [)" + accessors + "]" +
           (more.empty() ? "" : ", " + more);
}

// The colour at (x, y) of a quad whose corners carry c[0..3], interpolated over its two
// triangles (0, 1, 2) and (0, 2, 3).
RGB quad_colour(const RGB c[4], float x, float y) {
    if (x >= y) return c[0] * (1.f - x) + c[1] * (x - y) + c[2] * y;
    return c[0] * (1.f - y) + c[2] * x + c[3] * (y - x);
}

}  // namespace

TEST_CASE("glTF: COLOR_0 multiplies the base colour, interpolated over each triangle",
          "[gltf][mesh-file]") {
    test::TempDir dir;
    GltfBuffer buf;
    const int pos = buf.add(kQuad);
    const int idx = buf.add(std::vector<uint16_t>{0, 1, 2, 0, 2, 3});
    // Normalised bytes (linear, as the spec says), RGBA with an alpha that is not read.
    const int col = buf.add(
        std::vector<uint8_t>{255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 128});
    buf.write(
        dir, "colours",
        one_mesh(R"("attributes": {"POSITION": 0, "COLOR_0": 2}, "indices": 1, "material": 0)",
                 accessor(pos, 5126, 4, "VEC3") + ", " + accessor(idx, 5123, 6, "SCALAR") + ", " +
                     accessor(col, 5121, 4, "VEC4", ", \"normalized\": true"),
                 R"("materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 1, 1],
                          "metallicFactor": 0}}])"));
    const MeshFile file = load_mesh_file(dir.file("colours.gltf"));
    REQUIRE(file.parts.size() == 1);
    CHECK(file.parts[0].mesh.colors.size() == 12);
    CHECK(file.materials[0].vertex_colors);
    bool noted = false;
    for (const std::string& n : file.notes) noted |= n.find("COLOR_0's alpha ignored") != n.npos;
    CHECK(noted);
    test::write_scene(dir.file("s.xml"), R"(<triangle_mesh src="colours.gltf"/>)");
    const RGB corners[4] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
    // The dielectric base: diffuse 0.96 x base x colour beside the GGX reflection's 0.01
    // head-on (test_mesh_files.cpp derives both).
    const double worst = test::worst_pixel(dir.file("s.xml"), [&](float x, float y) {
        return RGB{1.f, 0.5f, 1.f} * quad_colour(corners, x, y) * 0.96f + RGB{0.01f};
    });
    INFO("worst pixel difference " << worst);
    CHECK(worst < 0.02);

    // Without a material, glTF's default (white, metallic 1, roughness 1) takes the colours:
    // a white conductor of GGX alpha 1 head-on under irradiance pi reflects
    // F D G / 4 x pi = 1 / (4 pi) x pi = 0.25, times the colour.
    GltfBuffer plain;
    plain.add(kQuad);
    plain.add(std::vector<uint16_t>{0, 1, 2, 0, 2, 3});
    plain.add(std::vector<float>{1, 0.5f, 0, 1, 1, 1, 0, 0.5f, 1, 0.2f, 0.2f, 0.2f});
    plain.write(dir, "plain",
                one_mesh(R"("attributes": {"POSITION": 0, "COLOR_0": 2}, "indices": 1)",
                         accessor(0, 5126, 4, "VEC3") + ", " + accessor(1, 5123, 6, "SCALAR") +
                             ", " + accessor(2, 5126, 4, "VEC3")));
    test::write_scene(dir.file("p.xml"), R"(<triangle_mesh src="plain.gltf"/>)");
    const RGB plain_corners[4] = {{1, 0.5f, 0}, {1, 1, 1}, {0, 0.5f, 1}, {0.2f, 0.2f, 0.2f}};
    const double worst_plain = test::worst_pixel(dir.file("p.xml"), [&](float x, float y) {
        return quad_colour(plain_corners, x, y) * 0.25f;
    });
    INFO("worst pixel difference, default material " << worst_plain);
    CHECK(worst_plain < 0.02);
}

TEST_CASE("glTF: triangle strips and fans unroll with the spec's winding", "[gltf][mesh-file]") {
    // Five vertices: a strip turns every other triangle, a fan pivots on the first vertex.
    CHECK(gltf_triangle_list({0, 1, 2, 3, 4}, 5) ==
          std::vector<uint32_t>{0, 1, 2, 1, 3, 2, 2, 3, 4});
    CHECK(gltf_triangle_list({0, 1, 2, 3, 4}, 6) ==
          std::vector<uint32_t>{1, 2, 0, 2, 3, 0, 3, 4, 0});
    CHECK(gltf_triangle_list({0, 1, 2}, 4) == std::vector<uint32_t>{0, 1, 2});
    CHECK(gltf_triangle_list({0, 1}, 5).empty());

    test::TempDir dir;
    for (const auto& [mode, order] :
         {std::pair<int, std::vector<uint16_t>>{5, {0, 1, 3, 2}}, {6, {0, 1, 2, 3}}}) {
        // (Built by appending: GCC 12 warns falsely on "m" + std::to_string(mode).)
        std::string name = "mode";
        name += std::to_string(mode);
        GltfBuffer buf;
        buf.add(kQuad);
        buf.add(order);
        buf.write(
            dir, name,
            one_mesh(R"("attributes": {"POSITION": 0}, "indices": 1, "material": 0, "mode": )" +
                         std::to_string(mode),
                     accessor(0, 5126, 4, "VEC3") + ", " + accessor(1, 5123, 4, "SCALAR"),
                     R"("materials": [{"pbrMetallicRoughness": {"baseColorFactor":
                              [0.2, 0.4, 0.6, 1], "metallicFactor": 0}}])"));
        const MeshFile file = load_mesh_file(dir.file(name + ".gltf"));
        REQUIRE(file.parts.size() == 1);
        const TriangleMesh& m = file.parts[0].mesh;
        REQUIRE(m.num_triangles() == 2);
        for (uint32_t t = 0; t < 2; ++t) {
            Vec3 p0, p1, p2;
            m.corners(t, p0, p1, p2);
            CHECK(cross(p1 - p0, p2 - p0).z == Approx(1.f));  // each faces +z, area 1/2
        }
        test::write_scene(dir.file("s.xml"), "<triangle_mesh src=\"" + name + ".gltf\"/>");
        const double worst = test::worst_pixel(dir.file("s.xml"), [](float, float) {
            return RGB{0.2f, 0.4f, 0.6f} * 0.96f + RGB{0.01f};
        });
        INFO("mode " << mode << ": worst pixel difference " << worst);
        CHECK(worst < 0.02);
    }
}

TEST_CASE("glTF: sparse accessors replace the elements they list, over zeros without a view",
          "[gltf][mesh-file]") {
    test::TempDir dir;
    auto write = [&](const std::vector<uint16_t>& colour_at) {
        GltfBuffer buf;
        // Vertex 2 is far off in the dense data; the sparse part puts it at (1, 1, 0).
        buf.add(std::vector<float>{0, 0, 0, 1, 0, 0, 5, 5, 0, 0, 1, 0});
        buf.add(std::vector<uint16_t>{0, 1, 2, 0, 2, 3});
        buf.add(std::vector<uint8_t>{2});
        buf.add(std::vector<float>{1, 1, 0});
        buf.add(colour_at);
        buf.add(std::vector<float>{1, 1, 1, 0.5f, 0.25f, 1});
        const std::string sparse_pos =
            R"(, "sparse": {"count": 1, "indices": {"bufferView": 2, "componentType": 5121},
                "values": {"bufferView": 3}})";
        // COLOR_0 has no dense data: zeros but at the listed vertices.
        const std::string colours =
            R"({"componentType": 5126, "count": 4, "type": "VEC3", "sparse": {"count": )" +
            std::to_string(colour_at.size()) +
            R"(, "indices": {"bufferView": 4, "componentType": 5123}, "values": {"bufferView": 5}}})";
        buf.write(dir, "sparse",
                  one_mesh(R"("attributes": {"POSITION": 0, "COLOR_0": 2}, "indices": 1)",
                           accessor(0, 5126, 4, "VEC3", sparse_pos) + ", " +
                               accessor(1, 5123, 6, "SCALAR") + ", " + colours));
    };
    write({0, 2});
    const MeshFile file = load_mesh_file(dir.file("sparse.gltf"));
    REQUIRE(file.parts.size() == 1);
    const TriangleMesh& m = file.parts[0].mesh;
    CHECK(m.vertex(2).x == 1.f);
    CHECK(m.vertex(2).y == 1.f);
    CHECK(m.colors == std::vector<float>{1, 1, 1, 0, 0, 0, 0.5f, 0.25f, 1, 0, 0, 0});
    // Indices must increase and stay below the count.
    for (const std::vector<uint16_t>& bad : {std::vector<uint16_t>{2, 0}, {0, 7}}) {
        write(bad);
        try {
            load_mesh_file(dir.file("sparse.gltf"));
            FAIL("accepted sparse indices " << bad[0] << " " << bad[1]);
        } catch (const InputError& e) {
            CHECK_THAT(e.what(), Catch::Contains("sparse.gltf") &&
                                     Catch::Contains("accessor 2: sparse indices must increase"));
        }
    }
}

TEST_CASE("glTF: normalTexture.scale scales the map's tangent-plane part", "[gltf][texture]") {
    const Vec3 n{0, 0, 1}, dpdu{1, 0, 0};
    const RGB texel{0.75f, 0.5f, 0.75f};  // (0.5, 0, 0.5) in the tangent frame
    const Vec3 one = normal_mapped(n, dpdu, texel);
    CHECK(one.x == Approx(std::sqrt(0.5f)));
    const Vec3 two = normal_mapped(n, dpdu, texel, 2.f);
    CHECK(two.x == Approx(1.f / std::sqrt(1.25f)));
    CHECK(two.z == Approx(0.5f / std::sqrt(1.25f)));
    const Vec3 none = normal_mapped(n, dpdu, texel, 0.f);
    CHECK(none.z == Approx(1.f));

    test::TempDir dir;
    const unsigned char px[] = {192, 128, 192, 192, 128, 192, 192, 128, 192, 192, 128, 192};
    REQUIRE(stbi_write_png(dir.file("n.png").c_str(), 2, 2, 3, px, 6) != 0);
    GltfBuffer buf;
    buf.add(kQuad);
    buf.add(std::vector<uint16_t>{0, 1, 2, 0, 2, 3});
    buf.add(std::vector<float>{0, 1, 1, 1, 1, 0, 0, 0});
    buf.write(
        dir, "bumpy",
        one_mesh(R"("attributes": {"POSITION": 0, "TEXCOORD_0": 2}, "indices": 1, "material": 0)",
                 accessor(0, 5126, 4, "VEC3") + ", " + accessor(1, 5123, 6, "SCALAR") + ", " +
                     accessor(2, 5126, 4, "VEC2"),
                 R"("materials": [{"normalTexture": {"index": 0, "scale": 0.25}}],
                          "textures": [{"source": 0}], "images": [{"uri": "n.png"}])"));
    const MeshFile file = load_mesh_file(dir.file("bumpy.gltf"));
    CHECK(file.materials[0].normal_scale == 0.25f);
    for (const std::string& note : file.notes) CHECK(note.find("scale") == note.npos);
    test::write_scene(dir.file("s.xml"), R"(<triangle_mesh src="bumpy.gltf"/>)");
    const Scene s = load_scene(dir.file("s.xml"));
    CHECK(s.materials.back().normal_scale == 0.25f);
}

TEST_CASE("glTF: an orthographic camera is the model's view, xmag and ymag its half extents",
          "[gltf][camera]") {
    test::TempDir dir;
    auto write = [&](const std::string& mags) {
        GltfBuffer buf;
        buf.add(kQuad);
        buf.add(std::vector<uint16_t>{0, 1, 2, 0, 2, 3});
        buf.write(dir, "ortho",
                  R"("scene": 0, "scenes": [{"nodes": [0, 1]}],
  "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0.5, 0.5, 5]}],
  "cameras": [{"type": "orthographic", "orthographic": {)" +
                      mags +
                      R"(, "znear": 0.1, "zfar": 10}}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
  "accessors": [)" + accessor(0, 5126, 4, "VEC3") +
                      ", " + accessor(1, 5123, 6, "SCALAR") + "]");
    };
    write(R"("xmag": 1, "ymag": 0.5)");
    const Scene s = model_scene(dir.file("ortho.gltf"));
    CHECK(s.camera.type == CameraType::Orthographic);
    REQUIRE(s.camera.width == 2 * s.camera.height);
    // The image's corners see (0.5 -+ 1, 0.5 +- 0.5): its top left and bottom right.
    Vec3 o, d;
    s.camera.generate(0.f, 0.f, o, d);
    CHECK(o.x == Approx(-0.5f).margin(1e-4));
    CHECK(o.y == Approx(1.f).margin(1e-4));
    CHECK(d.z == Approx(-1.f));
    s.camera.generate(float(s.camera.width), float(s.camera.height), o, d);
    CHECK(o.x == Approx(1.5f).margin(1e-4));
    CHECK(o.y == Approx(0.f).margin(1e-4));
    write(R"("xmag": 0, "ymag": 0.5)");
    CHECK_THROWS_WITH(model_scene(dir.file("ortho.gltf")),
                      Catch::Contains("ortho.gltf") && Catch::Contains("xmag and ymag"));
}

TEST_CASE("glTF: KHR_mesh_quantization's integer attributes, and an unread required extension",
          "[gltf][mesh-file]") {
    test::TempDir dir;
    auto write = [&](const std::string& extensions) {
        GltfBuffer buf;
        // Normalised shorts (-32768 maps to -1 as 32767 does, the spec's rule), normalised
        // bytes for the normals, plain unsigned bytes for the uv.
        buf.add(std::vector<int16_t>{-32768, 0, 0, 32767, 0, 0, 32767, 32767, 0, -32767, 32767, 0});
        buf.add(std::vector<int8_t>{0, 0, 127, 0, 0, 127, 0, 0, 127, 0, 0, 127});
        buf.add(std::vector<uint8_t>{0, 2, 2, 2, 2, 0, 0, 0});
        buf.add(std::vector<uint16_t>{0, 1, 2, 0, 2, 3});
        buf.write(
            dir, "quantized",
            extensions +
                one_mesh(R"("attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                            "indices": 3, "material": 0)",
                         accessor(0, 5122, 4, "VEC3", ", \"normalized\": true") + ", " +
                             accessor(1, 5120, 4, "VEC3", ", \"normalized\": true") + ", " +
                             accessor(2, 5121, 4, "VEC2") + ", " + accessor(3, 5123, 6, "SCALAR"),
                         R"("materials": [{"normalTexture": {"index": 0}}],
                            "textures": [{"source": 0}], "images": [{"uri": "n.png"}])"));
    };
    const unsigned char px[] = {128, 128, 255};
    REQUIRE(stbi_write_png(dir.file("n.png").c_str(), 1, 1, 3, px, 3) != 0);
    write(R"("extensionsUsed": ["KHR_mesh_quantization"],
             "extensionsRequired": ["KHR_mesh_quantization"], )");
    const MeshFile file = load_mesh_file(dir.file("quantized.gltf"));
    REQUIRE(file.parts.size() == 1);
    const TriangleMesh& m = file.parts[0].mesh;
    CHECK(m.vertex(0).x == -1.f);
    CHECK(m.vertex(2).x == 1.f);
    CHECK(m.vertex(2).y == 1.f);
    CHECK(m.vertex(3).x == Approx(-1.f));
    CHECK(m.vertex_normal(1).z == 1.f);
    // The uv as they are (glTF's v flipped to foton's).
    CHECK(m.uvs == std::vector<float>{0, -1, 2, -1, 2, 1, 0, 1});
    // Without the extension, integer positions are not glTF.
    write("");
    CHECK_THROWS_WITH(load_mesh_file(dir.file("quantized.gltf")),
                      Catch::Contains("POSITION, accessor 0: component type 5122") &&
                          Catch::Contains("KHR_mesh_quantization"));
    // A required extension foton does not read is an error naming it.
    write(R"("extensionsUsed": ["KHR_mesh_quantization", "KHR_draco_mesh_compression"],
             "extensionsRequired": ["KHR_mesh_quantization", "KHR_draco_mesh_compression"], )");
    CHECK_THROWS_WITH(load_mesh_file(dir.file("quantized.gltf")),
                      Catch::Contains("quantized.gltf") &&
                          Catch::Contains("requires KHR_draco_mesh_compression"));
}

TEST_CASE("glTF: a normal map on the second uv set turns in that set's tangent frame",
          "[gltf][texture]") {
    test::TempDir dir;
    // (192, 128, 192) read linearly: about (0.5, 0, 0.5) in the tangent frame, leaning the
    // normal halfway towards dp/du.
    const unsigned char n[] = {192, 128, 192};
    REQUIRE(stbi_write_png(dir.file("n.png").c_str(), 1, 1, 3, n, 3) != 0);
    const unsigned char c[] = {200, 200, 200};
    REQUIRE(stbi_write_png(dir.file("c.png").c_str(), 1, 1, 3, c, 3) != 0);
    for (int set : {0, 1}) {
        GltfBuffer buf;
        buf.add(kQuad);
        buf.add(std::vector<uint16_t>{0, 1, 2, 0, 2, 3});
        // TEXCOORD_0: u along x; TEXCOORD_1: u along y (glTF's v runs down the image).
        buf.add(std::vector<float>{0, 1, 1, 1, 1, 0, 0, 0});
        buf.add(std::vector<float>{0, 0, 0, 1, 1, 1, 1, 0});
        buf.write(
            dir, "frame",
            one_mesh(R"("attributes": {"POSITION": 0, "TEXCOORD_0": 2, "TEXCOORD_1": 3},
                              "indices": 1, "material": 0)",
                     accessor(0, 5126, 4, "VEC3") + ", " + accessor(1, 5123, 6, "SCALAR") + ", " +
                         accessor(2, 5126, 4, "VEC2") + ", " + accessor(3, 5126, 4, "VEC2"),
                     R"("materials": [{"pbrMetallicRoughness": {"baseColorTexture":
                                {"index": 1}}, "normalTexture": {"index": 0, "texCoord": )" +
                         std::to_string(set) + R"(}}],
                              "textures": [{"source": 0}, {"source": 1}],
                              "images": [{"uri": "n.png"}, {"uri": "c.png"}])"));
        test::write_scene(dir.file("s.xml"), R"(<triangle_mesh src="frame.gltf"/>)");
        const Scene s = load_scene(dir.file("s.xml"));
        const SurfacePoint sp =
            surface_at(s, 0, 0, 5.f, 0.2f, 0.1f, Vec3{0.5f, 0.4f, 5.f}, Vec3{0.f, 0.f, -1.f});
        INFO("normal map on TEXCOORD_" << set << ": ns " << sp.ns.x << " " << sp.ns.y << " "
                                       << sp.ns.z);
        const float along = set == 0 ? sp.ns.x : sp.ns.y, across = set == 0 ? sp.ns.y : sp.ns.x;
        CHECK(along == Approx(std::sqrt(0.5f)).margin(0.02));
        CHECK(std::fabs(across) < 0.02f);
    }
}
