#include <catch2/catch.hpp>

#include "engine/core/error.h"
#include "engine/scene/obj_loader.h"
#include "test_util.h"

using namespace foton;

namespace {
// Expects parse_obj to fail at `line` with a message containing `what`.
void expect_error(const std::string& text, int line, const std::string& what) {
    try {
        parse_obj(text, "m.obj");
        FAIL("no error for: " << text);
    } catch (const InputError& e) {
        CHECK(e.line() == line);
        CHECK_THAT(e.what(), Catch::Contains(what));
        CHECK_THAT(e.what(), Catch::StartsWith("m.obj"));
    }
}
}  // namespace

TEST_CASE("OBJ: positions, polygons, normals, negative indices", "[obj][fast]") {
    const ObjLoadResult r = parse_obj(
        "# quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\ng group\nf 1 2 3 4\n", "q.obj");
    CHECK(r.mesh.num_triangles() == 2);
    CHECK(r.mesh.num_vertices() == 4);
    CHECK_FALSE(r.has_normals);
    const ObjLoadResult n = parse_obj(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvt 0.5 0.5\nf 1//1 2//1 3//1\nf -3/1/1 -2/1/1 "
        "-1/1/1\n",
        "n.obj");
    CHECK(n.has_normals);
    CHECK(n.mesh.num_triangles() == 2);
    CHECK(n.mesh.normals.size() == n.mesh.positions.size());
    CHECK(n.mesh.vertex_normal(0).z == 1.f);
}

TEST_CASE("OBJ: texture coordinates, materials by face, mtllib", "[obj][fast]") {
    // Two quads sharing an edge, with uvs split along it, in two materials.
    const ObjLoadResult r = parse_obj(
        "mtllib a b.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0 0\nvt 0 1\n"
        "usemtl red\nf 1/1 2/2 3/3 4/4\nusemtl blue\nf 2/5 5/2 6/3 3/6\nusemtl red\nf 1/1 2/2 "
        "4/4\n",
        "m.obj");
    REQUIRE(r.libraries.size() == 1);
    CHECK(r.libraries[0].file == "a b.mtl");
    CHECK(r.libraries[0].line == 1);
    REQUIRE(r.material_names == std::vector<std::string>{"red", "blue"});
    CHECK(r.material_lines == std::vector<int>{14, 16});
    CHECK(r.triangle_material == std::vector<int32_t>{0, 0, 1, 1, 0});
    CHECK(r.mesh.uvs.size() == 2 * r.mesh.num_vertices());
    // Vertices 2 and 3 carry two uvs each: welded into 8 (position, uv) pairs.
    CHECK(r.mesh.num_vertices() == 8);
    // Normals from the faces, shared across the uv seam.
    REQUIRE(r.mesh.normals.size() == r.mesh.positions.size());
    CHECK_FALSE(r.has_normals);
    for (uint32_t v = 0; v < r.mesh.num_vertices(); ++v)
        CHECK(r.mesh.vertex_normal(v).z == Approx(1.f));
    expect_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/2 2/1 3/1\n", 4, "texture coordinate index 2");
    expect_error("usemtl\n", 1, "usemtl needs a material name");
    expect_error("mtllib  \n", 1, "mtllib needs a file name");
}

TEST_CASE("OBJ: bad input is reported with its line", "[obj][bad-input][fast]") {
    expect_error("v 0 0 0\nv 1 0 0\nf 1 2 3\n", 3, "vertex index 3 out of range");
    expect_error("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 0 1 2\n", 4, "out of range");
    expect_error("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 -4\n", 4, "out of range");
    expect_error("v 0 0 0\nv 1 nan 0\n", 2, "NaN or infinite");
    expect_error("v 0 0 0\nv 1 inf 0\n", 2, "NaN or infinite");
    expect_error("v 0 0 abc\n", 1, "malformed number");
    expect_error("v 0 0\n", 1, "missing coordinate");
    expect_error("v 0 0 0\nv 1 0 0\nf 1 2\n", 3, "face with 2 corners");
    expect_error("v 0 0 0\nbogus 1 2\n", 2, "unknown OBJ statement");
    expect_error("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 x\n", 4, "malformed vertex index");
    expect_error("v 0 0 0\n", 0, "no faces");
    expect_error("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", 0, "degenerate");
    CHECK_THROWS_AS(load_obj("/nonexistent/mesh.obj"), InputError);
}

TEST_CASE("OBJ: degenerate triangles are skipped and counted", "[obj][bad-input][fast]") {
    const ObjLoadResult r =
        parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\nf 1 1 3\n", "d.obj");
    CHECK(r.mesh.num_triangles() == 1);
    CHECK(r.degenerate_skipped == 2);
}

TEST_CASE("OBJ: the shared meshes load with their documented sizes", "[obj][fast]") {
    const ObjLoadResult bunny = load_obj(test::shared_path("meshes/bunny.obj"));
    CHECK(bunny.mesh.num_triangles() == 69451);
    CHECK(bunny.degenerate_skipped == 0);
    const ObjLoadResult teapot = load_obj(test::shared_path("meshes/teapot.obj"));
    CHECK(teapot.mesh.num_triangles() + teapot.degenerate_skipped == 6320);
}
