// Meshes made from other shapes (engine/scene/mesh_shapes.h): Loop subdivision's counts,
// closedness and orientation, its affine invariance, its limit points (a control vertex's
// limit is the same whatever the level), flat meshes staying flat with straight rims; the
// tessellated disk and cylinder keep the true area; and pbrt-v4's loopsubdiv, disk and
// cylinder shapes import, with errors at their line.
#include <catch2/catch.hpp>
#include <cmath>
#include <map>

#include "engine/core/error.h"
#include "engine/scene/mesh_shapes.h"
#include "engine/scene/pbrt_loader.h"

using namespace foton;

namespace {

// An octahedron of unit radius, outward winding.
TriangleMesh octahedron() {
    TriangleMesh m;
    m.positions = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    m.indices = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    return m;
}

// A flat n x n grid of squares in z = 0, two triangles each.
TriangleMesh flat_grid(int n) {
    TriangleMesh m;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x) m.positions.insert(m.positions.end(), {float(x), float(y), 0});
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            const uint32_t a = uint32_t(y * (n + 1) + x), b = a + 1, c = a + uint32_t(n) + 1,
                           d = c + 1;
            m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
        }
    }
    return m;
}

// The sum of f(a, b, c) over the mesh's triangles.
template <class F>
double over_triangles(const TriangleMesh& m, F f) {
    double sum = 0.0;
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        Vec3 a, b, c;
        m.corners(uint32_t(t), a, b, c);
        sum += f(a, b, c);
    }
    return sum;
}

double signed_volume(const TriangleMesh& m) {
    return over_triangles(m, [](Vec3 a, Vec3 b, Vec3 c) { return dot(a, cross(b, c)) / 6.0; });
}

double area(const TriangleMesh& m) {
    return over_triangles(m,
                          [](Vec3 a, Vec3 b, Vec3 c) { return 0.5 * length(cross(b - a, c - a)); });
}

}  // namespace

TEST_CASE("Loop subdivision: counts, a closed surface, orientation and limit points",
          "[mesh_shapes][fast]") {
    const TriangleMesh control = octahedron();
    for (int levels = 0; levels <= 3; ++levels) {
        const TriangleMesh m = loop_subdivide(control, levels);
        INFO("levels " << levels);
        CHECK(m.num_triangles() == 8u << (2 * levels));
        // Euler: V - E + F = 2 on a closed genus-0 surface, E = 3F / 2.
        CHECK(int(m.num_vertices()) - 3 * int(m.num_triangles()) / 2 + int(m.num_triangles()) == 2);
        // Closed: every edge has two triangles, traversed once each way (one orientation).
        std::map<std::pair<uint32_t, uint32_t>, int> directed;
        for (std::size_t i = 0; i < m.indices.size(); i += 3)
            for (int k = 0; k < 3; ++k)
                ++directed[{m.indices[i + std::size_t(k)],
                            m.indices[i + std::size_t((k + 1) % 3)]}];
        bool paired = true;
        for (const auto& [e, n] : directed)
            paired = paired && n == 1 && directed.count({e.second, e.first});
        CHECK(paired);
        // Outward, and shrunk inside the control polyhedron (Loop's surface is not
        // interpolating): volume below the octahedron's 4/3.
        CHECK(signed_volume(m) > 0.0);
        CHECK(signed_volume(m) <= 4.0 / 3.0 + 1e-6);
        CHECK(m.normals.size() == m.positions.size());
    }
    // The control vertices keep their indices, and each one's limit point does not depend on
    // how many levels were taken first.
    const TriangleMesh one = loop_subdivide(control, 1), four = loop_subdivide(control, 4);
    for (uint32_t i = 0; i < 6; ++i) {
        CHECK(one.vertex(i).x == Approx(four.vertex(i).x).margin(1e-5));
        CHECK(one.vertex(i).y == Approx(four.vertex(i).y).margin(1e-5));
        CHECK(one.vertex(i).z == Approx(four.vertex(i).z).margin(1e-5));
    }
    // By symmetry each limit point lies on its axis; valence 4: chi = 1 / (4 + 3 / (8 beta))
    // with beta = 3 / 32, so the limit of (1, 0, 0) is (1 - 4 chi) = 0.5 along x.
    CHECK(four.vertex(0).x == Approx(0.5f).margin(1e-5));
    CHECK(four.vertex(0).y == Approx(0.f).margin(1e-6));
}

TEST_CASE("Loop subdivision: affine invariance, flat meshes stay flat, rims stay straight",
          "[mesh_shapes][fast]") {
    // Loop's weights sum to one: subdividing a moved mesh is moving the subdivided one.
    TriangleMesh moved = octahedron();
    const Affine xf = Affine::translate({1.f, -2.f, 3.f}) * Affine::scale({2.f, 0.5f, 1.f});
    moved.transform(xf);
    const TriangleMesh a = loop_subdivide(moved, 2);
    TriangleMesh b = loop_subdivide(octahedron(), 2);
    b.transform(xf);
    double worst = 0.0;
    for (uint32_t i = 0; i < a.num_vertices(); ++i)
        worst = std::max(worst, double(length(a.vertex(i) - b.vertex(i))));
    CHECK(worst < 1e-5);
    // A flat grid: every vertex stays in its plane and inside the square; the boundary stays
    // on the square's edges (its B-spline of collinear points is the line); the area is kept.
    const TriangleMesh g = loop_subdivide(flat_grid(4), 3);
    int off_plane = 0, outside = 0;
    for (uint32_t i = 0; i < g.num_vertices(); ++i) {
        const Vec3 p = g.vertex(i);
        off_plane += std::fabs(p.z) > 1e-6f ? 1 : 0;
        outside += (p.x < -1e-5f || p.x > 4.00001f || p.y < -1e-5f || p.y > 4.00001f) ? 1 : 0;
    }
    CHECK(off_plane == 0);
    CHECK(outside == 0);
    // The boundary's B-spline of collinear points is their line: away from the corners
    // (which the boundary rule rounds, as pbrt-v4's does: it knows no creases) the rim is
    // the square's edge. The grid's own vertices on y = 0 keep y = 0 exactly.
    for (uint32_t x = 1; x < 4; ++x) CHECK(g.vertex(x).y == 0.f);
    CHECK(g.vertex(0).x > 0.f);  // the corner, rounded
    CHECK(area(g) < 16.0);
    CHECK(area(g) > 15.5);
}

TEST_CASE("tessellated disks and cylinders keep their area", "[mesh_shapes][fast]") {
    const TriangleMesh d = tessellate_disk(0.5f, 2.f, 0.f, 2.f * kPi, 256);
    CHECK(area(d) == Approx(kPi * 4.0).epsilon(1e-5));
    for (std::size_t i = 0; i < d.positions.size(); i += 3) CHECK(d.positions[i + 2] == 0.5f);
    // Facing +z by winding too.
    Vec3 a, b, c;
    d.corners(0, a, b, c);
    CHECK(cross(b - a, c - a).z > 0.f);
    const TriangleMesh ring = tessellate_disk(0.f, 2.f, 1.f, 0.5f * kPi, 256);
    CHECK(area(ring) == Approx(0.25 * kPi * 3.0).epsilon(1e-5));
    const TriangleMesh cyl = tessellate_cylinder(1.5f, -1.f, 2.f, 2.f * kPi, 256);
    CHECK(area(cyl) == Approx(2.0 * kPi * 1.5 * 3.0).epsilon(1e-5));
    cyl.corners(0, a, b, c);
    const Vec3 n = cross(b - a, c - a), mid = (a + b + c) / 3.f;
    CHECK(dot(n, Vec3{mid.x, mid.y, 0.f}) > 0.f);  // outward
    // Within 0.02 % of the radius from the true cylinder.
    for (uint32_t i = 0; i < cyl.num_vertices(); ++i) {
        const Vec3 p = cyl.vertex(i);
        CHECK(std::hypot(p.x, p.y) == Approx(1.5).epsilon(2e-4));
    }
}

TEST_CASE("pbrt-v4: loopsubdiv, disk and cylinder import, and bad ones fail at their line",
          "[mesh_shapes][pbrt][fast]") {
    const std::string cube =
        R"(Shape "loopsubdiv" "integer levels" 2 "point3 P" [-1 -1 -1  1 -1 -1  1 1 -1  -1 1 -1
             -1 -1 1  1 -1 1  1 1 1  -1 1 1]
           "integer indices" [0 2 1 0 3 2  4 5 6 4 6 7  0 1 5 0 5 4  1 2 6 1 6 5  2 3 7 2 7 6
             3 0 4 3 4 7])";
    const Scene s = parse_pbrt_scene("WorldBegin\n" + cube +
                                         "\nAttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" "
                                         "[1 1 1]\nShape \"disk\" \"float radius\" 0.5 \"float "
                                         "height\" 3\nAttributeEnd\nShape \"cylinder\" \"float "
                                         "phimax\" 180\n",
                                     "shapes.pbrt", ".");
    // The emitting disk is tessellated (light sampling knows meshes); the cylinder is analytic.
    REQUIRE(s.meshes.size() == 2);
    CHECK(s.meshes[0].num_triangles() == 12u * 16u);
    CHECK(s.meshes[1].num_triangles() == 256u);
    REQUIRE(s.shapes.size() == 1);
    const ShapePrimitive& cyl = s.shapes[0].shapes()[0];
    CHECK(cyl.type == ShapeType::Cylinder);
    CHECK(cyl.phi_max == Approx(kPi));
    CHECK(cyl.height == Approx(2.f));
    CHECK(cyl.world_bounds().lo.z == Approx(-1.f));
    auto error_of = [](const std::string& body) -> std::string {
        try {
            parse_pbrt_scene("WorldBegin\n" + body + "\n", "bad.pbrt", ".");
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    CHECK_THAT(error_of(R"(Shape "loopsubdiv" "point3 P" [0 0 0 1 0 0 0 1 0 0 0 1 1 1 1]
        "integer indices" [0 1 2  1 0 3  0 1 4])"),
               Catch::Contains("bad.pbrt:2") && Catch::Contains("not manifold"));
    CHECK_THAT(error_of(R"(Shape "loopsubdiv" "integer levels" 11 "point3 P" [0 0 0 1 0 0 0 1 0]
        "integer indices" [0 1 2])"),
               Catch::Contains("levels must be in [0, 10]"));
    CHECK_THAT(error_of(R"(Shape "disk" "float radius" 1 "float innerradius" 2)"),
               Catch::Contains("bad.pbrt:2") && Catch::Contains("innerradius"));
    CHECK_THAT(error_of(R"(Shape "cylinder" "float zmin" 1 "float zmax" 1)"),
               Catch::Contains("zmin and zmax must differ"));
}
TEST_CASE("normals follow their surface through rotations, scales and mirrors",
          "[mesh_shapes][fast]") {
    // A normal n of a plane stays perpendicular to the transformed plane's tangents and on
    // the side the transformed n points to (the inverse transpose; its transpose once turned
    // a rotated disk light's normal from -y to +y, so it lit the ceiling).
    const Affine cases[] = {Affine::rotate({1, 0, 0}, 90.f), Affine::rotate({0.3f, -1, 2}, 37.f),
                            Affine::scale({2.f, 0.5f, 3.f}) * Affine::rotate({0, 1, 1}, 50.f),
                            Affine::scale({-1.f, 1.f, 1.f}) * Affine::rotate({1, 2, 3}, 20.f)};
    const Vec3 n = normalize(Vec3{0.2f, -0.5f, 0.9f});
    Vec3 t1, t2;
    orthonormal_basis(n, t1, t2);
    for (const Affine& xf : cases) {
        const Vec3 m = xf.normal(n);
        CHECK(std::fabs(dot(m, normalize(xf.vector(t1)))) < 1e-5f);
        CHECK(std::fabs(dot(m, normalize(xf.vector(t2)))) < 1e-5f);
        CHECK(dot(m, xf.vector(n)) > 0.f);
    }
    const Vec3 down = Affine::rotate({1, 0, 0}, 90.f).normal({0, 0, 1});
    CHECK(down.y == Approx(-1.f));
    // A disk light turned to face down lights what is below it.
    const Scene s = parse_pbrt_scene(R"(WorldBegin
        AttributeBegin AreaLightSource "diffuse" "rgb L" [1 1 1]
        Translate 0 4 0 Rotate 90 1 0 0 Shape "disk" AttributeEnd)",
                                     "disk.pbrt", ".");
    REQUIRE(s.meshes.size() == 1);
    Vec3 a, b, c;
    s.meshes[0].corners(0, a, b, c);
    CHECK(cross(b - a, c - a).y < 0.f);
    CHECK(s.meshes[0].normals[1] == Approx(-1.f));
}
