// Analytic shapes and CSG (issue 39): the polynomial root finder on known roots; each shape's
// crossings against the analytic answer and its implicit function sampled along the ray; the
// torus on random rays against a fine march; CSG trees of spheres against closed-form spans
// and against point classification; every backend equal with shapes in the scene; the
// surface a hit makes; a CSG sphere rendering as the scene's own sphere; bad input.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>

#include "engine/accel/intersector.h"
#include "engine/core/error.h"
#include "engine/core/polynomial.h"
#include "engine/core/rng.h"
#include "engine/scene/pbrt_loader.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/common/surface.h"
#include "image_checks.h"
#include "test_util.h"

using namespace foton;

namespace {

ShapePrimitive placed(ShapePrimitive s, const Affine& xf = Affine{}) {
    REQUIRE(s.place(xf));
    return s;
}

// The closest crossing of a single shape (world ray), or a negative t for none.
float first_hit(const ShapePrimitive& s, const Vec3& o, const Vec3& d, uint32_t* prim = nullptr) {
    float t;
    uint32_t p;
    if (!AnalyticShape(s).closest(o, d, 0.f, kInfinity, t, p)) return -1.f;
    if (prim) *prim = p;
    return t;
}

Vec3 unit_at(uint64_t i, uint64_t dim) {
    const float z = 2.f * rng::uniform(21, 0, i, dim) - 1.f;
    const float phi = 2.f * kPi * rng::uniform(21, 0, i, dim + 1);
    const float r = std::sqrt(std::max(0.f, 1.f - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
}

double torus_f(double R, double r, double x, double y, double z) {
    const double rho = std::sqrt(x * x + y * y);
    return (rho - R) * (rho - R) + z * z - r * r;
}

}  // namespace

TEST_CASE("shapes: polynomial roots are found in order and in range", "[shapes][fast]") {
    // (x - 1)(x - 2)(x + 3)(x - 0.5) = x^4 - 0.5 x^3 - 7 x^2 + 9.5 x - 3
    const double c[5] = {-3.0, 9.5, -7.0, -0.5, 1.0};
    double r[4];
    REQUIRE(polynomial_roots(c, 4, -10, 10, r) == 4);
    CHECK(r[0] == Approx(-3.0).margin(1e-12));
    CHECK(r[1] == Approx(0.5).margin(1e-12));
    CHECK(r[2] == Approx(1.0).margin(1e-12));
    CHECK(r[3] == Approx(2.0).margin(1e-12));
    REQUIRE(polynomial_roots(c, 4, 0.0, 1.5, r) == 2);  // only those in range
    CHECK(r[0] == Approx(0.5).margin(1e-12));
    // x^4 + 1 has no real root; (x^2 - 1e-8) two close ones.
    const double none[5] = {1.0, 0.0, 0.0, 0.0, 1.0};
    CHECK(polynomial_roots(none, 4, -1e3, 1e3, r) == 0);
    const double close[3] = {-1e-8, 0.0, 1.0};
    REQUIRE(polynomial_roots(close, 2, -1, 1, r) == 2);
    CHECK(r[1] == Approx(1e-4).epsilon(1e-12));
    // A cubic with a leading zero coefficient is the quadratic below it.
    const double cubic[4] = {-2.0, 0.0, 1.0, 0.0};
    REQUIRE(polynomial_roots(cubic, 3, -5, 5, r) == 2);
    CHECK(r[1] == Approx(std::sqrt(2.0)).epsilon(1e-14));
}

TEST_CASE(
    "shapes: disk, cylinder, cone, paraboloid, hyperboloid and torus meet rays where "
    "their equations say",
    "[shapes][fast]") {
    ShapePrimitive disk;
    disk.type = ShapeType::Disk;
    disk.radius = 2.f;
    disk.inner_radius = 0.5f;
    disk.phi_max = 1.5f * kPi;
    const ShapePrimitive d = placed(disk);
    CHECK(first_hit(d, {1.f, 0.2f, 5.f}, {0, 0, -1}) == Approx(5.f));
    CHECK(first_hit(d, {0.2f, 0.2f, 5.f}, {0, 0, -1}) < 0.f);   // the hole
    CHECK(first_hit(d, {1.f, -0.2f, 5.f}, {0, 0, -1}) < 0.f);   // beyond phi_max (phi ~ 348 deg)
    CHECK(first_hit(d, {-1.f, -0.2f, 5.f}, {0, 0, -1}) > 0.f);  // phi ~ 191 deg

    ShapePrimitive cyl;
    cyl.type = ShapeType::Cylinder;
    cyl.radius = 0.5f;
    cyl.height = 2.f;
    // Open: from outside across the axis the near side, from inside the far side.
    CHECK(first_hit(placed(cyl), {-3.f, 0.f, 1.f}, {1, 0, 0}) == Approx(2.5f));
    CHECK(first_hit(placed(cyl), {0.f, 0.f, 1.f}, {1, 0, 0}) == Approx(0.5f));
    CHECK(first_hit(placed(cyl), {0.f, 0.f, -1.f}, {0, 0, 1}) < 0.f);  // along the open axis
    cyl.capped = true;
    uint32_t prim = 99;
    CHECK(first_hit(placed(cyl), {0.1f, 0.f, -1.f}, {0, 0, 1}, &prim) == Approx(1.f));
    CHECK(prim_part(prim) == 1);  // the bottom cap
    CHECK(first_hit(placed(cyl), {0.1f, 0.f, 5.f}, {0, 0, -1}, &prim) == Approx(3.f));
    CHECK(prim_part(prim) == 2);

    ShapePrimitive cone;
    cone.type = ShapeType::Cone;
    cone.radius = 1.f;
    cone.height = 2.f;
    // At height z the cone's radius is 1 - z / 2.
    for (float z : {0.2f, 1.f, 1.7f})
        CHECK(first_hit(placed(cone), {-5.f, 0.f, z}, {1, 0, 0}) ==
              Approx(5.f - (1.f - z / 2.f)).epsilon(1e-6));
    CHECK(first_hit(placed(cone), {-5.f, 0.f, 2.5f}, {1, 0, 0}) < 0.f);  // the other nappe

    // The paraboloid x^2 + y^2 = z (radius 1 at height 1) and the hyperboloid of waist 0.5 and
    // ends of radius 1 over height 2: at height z their radii are sqrt(z) and
    // sqrt(0.25 + 0.75 (z - 1)^2).
    ShapePrimitive para;
    para.type = ShapeType::Paraboloid;
    para.radius = 1.f;
    para.height = 1.f;
    ShapePrimitive hyper;
    hyper.type = ShapeType::Hyperboloid;
    hyper.radius = 1.f;
    hyper.inner_radius = 0.5f;
    hyper.height = 2.f;
    for (float z : {0.1f, 0.5f, 0.9f}) {
        CHECK(first_hit(placed(para), {-5.f, 0.f, z}, {1, 0, 0}) ==
              Approx(5.f - std::sqrt(z)).epsilon(1e-6));
        const float zh = 2.f * z;
        CHECK(first_hit(placed(hyper), {-5.f, 0.f, zh}, {1, 0, 0}) ==
              Approx(5.f - std::sqrt(0.25f + 0.75f * (zh - 1.f) * (zh - 1.f))).epsilon(1e-6));
    }
    // Open: down the axis nothing but the paraboloid's vertex; capped: the top first.
    CHECK(first_hit(placed(hyper), {0.f, 0.f, 5.f}, {0, 0, -1}) < 0.f);
    CHECK(first_hit(placed(para), {0.f, 0.f, 5.f}, {0, 0, -1}) == Approx(5.f));
    para.capped = hyper.capped = true;
    CHECK(first_hit(placed(para), {0.1f, 0.f, 5.f}, {0, 0, -1}, &prim) == Approx(4.f));
    CHECK(prim_part(prim) == 2);
    CHECK(first_hit(placed(hyper), {0.1f, 0.f, 5.f}, {0, 0, -1}, &prim) == Approx(3.f));
    CHECK(prim_part(prim) == 2);
    CHECK(first_hit(placed(hyper), {0.1f, 0.f, -5.f}, {0, 0, 1}, &prim) == Approx(5.f));
    CHECK(prim_part(prim) == 1);
    // Normals: the paraboloid's side at (1, 0, 1) along (2, 0, -1), the hyperboloid's waist
    // straight out.
    const Vec3 np = shape_surface(placed(para), 0, {1.f, 0.f, 1.f}).n;
    CHECK(np.x == Approx(2.f / std::sqrt(5.f)));
    CHECK(np.z == Approx(-1.f / std::sqrt(5.f)));
    const Vec3 nh = shape_surface(placed(hyper), 0, {0.f, 0.5f, 1.f}).n;
    CHECK(nh.y == Approx(1.f));

    ShapePrimitive torus;
    torus.type = ShapeType::Torus;
    torus.radius = 1.f;
    torus.minor_radius = 0.25f;
    const AnalyticShape ring(placed(torus));
    ShapeCrossing cr[kMaxShapeCrossings];
    const ShapeRay along_x = to_object_space(ring.shapes()[0], {-5.f, 0.f, 0.f}, {1, 0, 0});
    REQUIRE(shape_crossings(ring.shapes()[0], along_x, cr) == 4);
    const double want[4] = {3.75, 4.25, 5.75, 6.25};
    for (int i = 0; i < 4; ++i) CHECK(cr[i].t == Approx(want[i]).epsilon(1e-12));
    CHECK(first_hit(ring.shapes()[0], {1.f, 0.f, 3.f}, {0, 0, -1}) == Approx(2.75f));
    CHECK(first_hit(ring.shapes()[0], {0.f, 0.f, 3.f}, {0, 0, -1}) < 0.f);  // the hole
}

TEST_CASE("shapes: the torus' crossings equal a fine march of its implicit function",
          "[shapes][fast]") {
    ShapePrimitive torus;
    torus.type = ShapeType::Torus;
    torus.radius = 1.f;
    torus.minor_radius = 0.3f;
    const double R = 1.0, r = double(torus.minor_radius);
    int rays = 0, agree = 0, crossings = 0;
    for (uint64_t i = 0; i < uint64_t(test::scaled(2000)); ++i) {
        // From a random point within 3 of the centre, aimed near the tube.
        const Vec3 o = unit_at(i, 0) * 3.f;
        const Vec3 aim = Vec3{std::cos(6.3f * rng::uniform(22, i, 0, 0)),
                              std::sin(6.3f * rng::uniform(22, i, 0, 0)), 0.f} +
                         unit_at(i, 4) * 0.35f;
        const Vec3 dir = normalize(aim - o);
        const ShapeRay sr = to_object_space(placed(torus), o, dir);
        ShapeCrossing c[kMaxShapeCrossings];
        const int n = shape_crossings(placed(torus), sr, c);
        // Every crossing lies on the surface.
        for (int k = 0; k < n; ++k)
            CHECK(std::fabs(torus_f(R, r, sr.o[0] + c[k].t * sr.d[0], sr.o[1] + c[k].t * sr.d[1],
                                    sr.o[2] + c[k].t * sr.d[2])) < 1e-9);
        // The march: sign changes of f over t in [-1, 7] at steps of 1e-4.
        int changes = 0;
        double prev = torus_f(R, r, sr.o[0] - sr.d[0], sr.o[1] - sr.d[1], sr.o[2] - sr.d[2]);
        for (double t = -1.0 + 1e-4; t <= 7.0; t += 1e-4) {
            const double f =
                torus_f(R, r, sr.o[0] + t * sr.d[0], sr.o[1] + t * sr.d[1], sr.o[2] + t * sr.d[2]);
            changes += (f < 0.0) != (prev < 0.0);
            prev = f;
        }
        ++rays;
        agree += changes == n;
        crossings += n;
    }
    INFO(agree << " of " << rays << " rays agree; " << crossings << " crossings");
    // A ray grazing the tube within a step of the march may count differently.
    CHECK(agree >= rays - rays / 200);
    CHECK(crossings > rays);  // most rays meet the tube
}

namespace {

ShapePrimitive ball(const Vec3& c, float radius) {
    ShapePrimitive s;
    s.type = ShapeType::Sphere;
    s.radius = radius;
    return placed(s, Affine::translate(c));
}

// A and B: unit balls at x = 0 and x = 1.
AnalyticShape two_balls(CsgOp op) {
    AnalyticShape s;
    const uint32_t a = s.leaf(ball({0, 0, 0}, 1.f));
    const uint32_t b = s.leaf(ball({1, 0, 0}, 1.f));
    s.combine(op, a, b);
    s.finish();
    return s;
}

bool in_ball(const Vec3& p, const Vec3& c, float r) {
    return length_squared(p - c) < r * r;
}

}  // namespace

TEST_CASE("shapes: CSG of two spheres along their centres gives the closed-form spans",
          "[shapes][csg][fast]") {
    const Vec3 o{-5.f, 0.f, 0.f}, d{1.f, 0.f, 0.f};
    float t;
    uint32_t prim;
    // A spans x in [-1, 1], B [0, 2].
    REQUIRE(two_balls(CsgOp::Union).closest(o, d, 0.f, kInfinity, t, prim));
    CHECK(t == Approx(4.f));
    REQUIRE(two_balls(CsgOp::Intersection).closest(o, d, 0.f, kInfinity, t, prim));
    CHECK(t == Approx(5.f));
    CHECK(prim_shape(prim) == 1);  // entered through B
    const AnalyticShape diff = two_balls(CsgOp::Difference);
    REQUIRE(diff.closest(o, d, 0.f, kInfinity, t, prim));
    CHECK(t == Approx(4.f));
    // From inside A - B, out through B's surface at x = 0, which faces the other way there.
    REQUIRE(diff.closest({-0.5f, 0.f, 0.f}, d, 0.f, kInfinity, t, prim));
    CHECK(t == Approx(0.5f));
    CHECK(prim_shape(prim) == 1);
    CHECK(diff.inverted(1));
    CHECK_FALSE(diff.inverted(0));
    // Beyond x = 0 along the axis A - B is empty until B ends; nothing there.
    CHECK_FALSE(diff.closest({0.5f, 0.f, 0.f}, d, 0.f, kInfinity, t, prim));
    // The boxes: union both, intersection the overlap, difference A's.
    CHECK(two_balls(CsgOp::Union).bounds().hi.x == Approx(2.f));
    CHECK(two_balls(CsgOp::Intersection).bounds().lo.x == Approx(0.f));
    CHECK(two_balls(CsgOp::Difference).bounds().hi.x == Approx(1.f));
}

TEST_CASE("shapes: CSG hits on random rays equal point classification along the ray",
          "[shapes][csg][fast]") {
    // ((A u B) - C) n D over four balls, and the first change of inside-ness along each ray.
    const Vec3 ca{0, 0, 0}, cb{0.8f, 0.3f, 0}, cc{0.4f, 0.f, 0.5f}, cd{0.3f, 0.1f, -0.2f};
    const float ra = 1.f, rb = 0.7f, rc = 0.6f, rd = 1.1f;
    AnalyticShape s;
    const uint32_t a = s.leaf(ball(ca, ra)), b = s.leaf(ball(cb, rb));
    const uint32_t ab = s.combine(CsgOp::Union, a, b);
    const uint32_t c = s.leaf(ball(cc, rc));
    const uint32_t abc = s.combine(CsgOp::Difference, ab, c);
    s.combine(CsgOp::Intersection, abc, s.leaf(ball(cd, rd)));
    s.finish();
    auto inside = [&](const Vec3& p) {
        return (in_ball(p, ca, ra) || in_ball(p, cb, rb)) && !in_ball(p, cc, rc) &&
               in_ball(p, cd, rd);
    };
    int rays = 0, agree = 0, hits = 0;
    const float step = 2e-4f;
    for (uint64_t i = 0; i < uint64_t(test::scaled(600)); ++i) {
        const Vec3 o = unit_at(i, 10) * 3.f;
        const Vec3 dir = normalize(unit_at(i, 12) * 0.8f - o);
        float want = -1.f;
        bool prev = inside(o);
        for (int k = 1; k < int(6.f / step); ++k) {
            const float t = float(k) * step;
            const bool now = inside(o + dir * t);
            if (now != prev) {
                want = t;
                break;
            }
        }
        float t;
        uint32_t prim;
        const bool hit = s.closest(o, dir, 0.f, kInfinity, t, prim);
        ++rays;
        if (want < 0.f) {
            agree += !hit;
        } else {
            ++hits;
            agree += hit && std::fabs(t - want) <= step;
        }
    }
    INFO(agree << " of " << rays << " rays agree, " << hits << " hits");
    CHECK(agree == rays);
    CHECK(hits > rays / 4);
}

namespace {

const char* kShapeRoom = R"(<scene>
  <lights><point><position x="0" y="0" z="6"/><color r="1" g="1" b="1"/></point></lights>
  <objects>
    <quad><corner x="-3" y="-3" z="-1"/><edge1 x="6" y="0" z="0"/><edge2 x="0" y="6" z="0"/>
      <material type="lambert"/></quad>
    <sphere radius="0.4"><center x="2" y="2" z="0"/><material type="lambert"/></sphere>
    <disk radius="0.5"><center x="-2" y="2" z="0.2"/><normal x="0" y="1" z="1"/><material type="lambert"/></disk>
    <cylinder radius="0.4" capped="true"><base x="-2" y="-2" z="-1"/><top x="-2" y="-1" z="0.5"/><material type="lambert"/></cylinder>
    <cone radius="0.5" phi_max="200"><base x="2" y="-2" z="-1"/><apex x="2" y="-2" z="0.5"/><material type="lambert"/></cone>
    <paraboloid radius="0.4" capped="true"><apex x="-1" y="0" z="-1"/><top x="-1" y="0.3" z="0"/><material type="lambert"/></paraboloid>
    <hyperboloid radius="0.4" waist_radius="0.2" phi_max="300"><base x="1" y="0" z="-1"/><top x="1.2" y="0" z="0.2"/><material type="lambert"/></hyperboloid>
    <torus major_radius="0.6" minor_radius="0.2"><center x="0" y="0" z="0"/><axis x="1" y="1" z="1"/>
      <transform><scale x="1" y="1.5" z="1"/></transform><material type="lambert"/></torus>
    <csg op="difference"><transform><scale x="-1" y="1" z="1"/><translate x="0" y="2" z="0"/></transform>
      <box><min x="-0.5" y="-0.5" z="-0.5"/><max x="0.5" y="0.5" z="0.5"/></box>
      <sphere radius="0.6"/><material type="lambert"/></csg>
  </objects>
  <film width="8" height="8"/>
  <camera><eye x="0" y="0" z="8"/><target x="0" y="0" z="0"/><up x="0" y="1" z="0"/></camera>
</scene>)";

}  // namespace

TEST_CASE("shapes: every backend finds the same hits with shapes in the scene",
          "[shapes][accel][fast]") {
    const Scene s = parse_scene(kShapeRoom, "room.xml", ".");
    REQUIRE(s.shapes.size() == 7);
    RayBatch rays;
    for (uint32_t i = 0; i < 4000; ++i) {
        const Vec3 o = unit_at(i, 20) * 6.f;
        const Vec3 target{5.f * rng::uniform(23, 0, i, 0) - 2.5f,
                          5.f * rng::uniform(23, 0, i, 1) - 2.5f, rng::uniform(23, 0, i, 2) - 0.8f};
        rays.push(o, normalize(target - o), 0.f, i % 3 ? kInfinity : 4.f, i);
    }
    TraceCounters c;
    HitBatch want;
    make_intersector(s, AccelType::Brute)->intersect(rays, want, c);
    std::vector<uint8_t> want_occ;
    make_intersector(s, AccelType::Brute)->occluded(rays, want_occ, c);
    int on_shapes = 0;
    for (std::size_t i = 0; i < rays.size(); ++i)
        on_shapes += want.geom[i] != kNoHit && s.objects[want.geom[i]].kind == ObjectKind::Shape;
    CHECK(on_shapes > 200);
    CHECK(c.shape_tests > 0);
    for (AccelType a : {AccelType::BruteSimd, AccelType::Grid, AccelType::Bvh, AccelType::Embree,
                        AccelType::Octree, AccelType::KdTree}) {
        INFO(accel_name(a));
        const auto acc = make_intersector(s, a);
        HitBatch got;
        std::vector<uint8_t> occ;
        acc->intersect(rays, got, c);
        acc->occluded(rays, occ, c);
        int same = 0, same_occ = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            same +=
                got.geom[i] == want.geom[i] &&
                (want.geom[i] == kNoHit || (got.prim[i] == want.prim[i] && got.t[i] == want.t[i]));
            same_occ += occ[i] == want_occ[i];
        }
        CHECK(same == int(rays.size()));
        CHECK(same_occ == int(rays.size()));
    }
}

TEST_CASE("shapes: a hit's surface faces out of the solid, and the other way where subtracted",
          "[shapes][csg][fast]") {
    const Scene s = parse_scene(kShapeRoom, "room.xml", ".");
    const auto acc = make_intersector(s, AccelType::Bvh);
    TraceCounters c;
    int checked = 0;
    for (uint32_t i = 0; i < 3000; ++i) {
        const Vec3 o = unit_at(i, 30) * 6.f;
        const Vec3 d = normalize(Vec3{4.f * rng::uniform(24, 0, i, 0) - 2.f,
                                      4.f * rng::uniform(24, 0, i, 1) - 2.f, 0.f} -
                                 o);
        Hit1 h;
        if (!acc->intersect1({o.x, o.y, o.z, d.x, d.y, d.z, 0.f, kInfinity}, h, c)) continue;
        const Object& obj = s.objects[h.geom];
        if (obj.kind != ObjectKind::Shape || !s.shapes[obj.index].solid()) continue;
        const SurfacePoint sp = surface_at(s, h.geom, h.prim, h.t, h.u, h.v, o, d);
        // From outside every closed solid, a ray meets its front face: just beyond the
        // surface along -ng is inside (no hit back), just before it outside.
        CHECK(sp.front_face);
        CHECK(std::fabs(length(sp.ng) - 1.f) < 1e-5f);
        Hit1 back;
        const Vec3 q = sp.p - sp.ng * 1e-3f;  // inside the solid: leaving it, we meet it
        REQUIRE(acc->intersect1({q.x, q.y, q.z, d.x, d.y, d.z, 0.f, kInfinity}, back, c));
        const SurfacePoint exit = surface_at(s, back.geom, back.prim, back.t, back.u, back.v, q, d);
        if (back.geom == h.geom) CHECK_FALSE(exit.front_face);
        ++checked;
    }
    CHECK(checked > 300);
}

TEST_CASE("shapes: a CSG sphere renders as the scene's own sphere", "[shapes][csg][render]") {
    const std::string sphere =
        R"(<sphere radius="90"><center x="170" y="90" z="190"/><material type="lambert"/></sphere>)";
    const std::string csg =
        R"(<csg op="union"><sphere radius="90"><center x="170" y="90" z="190"/></sphere><material type="lambert"/></csg>)";
    std::ifstream in(test::source_path("scenes/cornell-diffuse.xml"));
    std::string room((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t at = room.find("<sphere radius=\"90\">");
    REQUIRE(at != std::string::npos);
    const std::size_t end = room.find("</sphere>", at) + std::string("</sphere>").size();
    auto with = [&](const std::string& object) {
        std::string x = room;
        x.replace(at, end - at, object);
        TestScene s(parse_scene(x, "box.xml", "."));
        s.set_resolution(48, 48);
        return render_test(s, 32, 0, 3);
    };
    const RenderResult a = with(sphere), b = with(csg);
    // The same sample streams meet the same surface (to rounding): nearly the same image.
    const ImageError e = compare_images(b.film, a.film);
    test::check_means(e.mean_a, e.mean_b, 0.002);
    INFO("rmse " << e.rmse << " of a mean " << e.mean_b.luminance());
    CHECK(e.rmse < 0.02 * e.mean_b.luminance());
}

TEST_CASE("shapes: bad shape input names its line", "[shapes][input][fast]") {
    auto error_of = [](const std::string& object) {
        const std::string xml = "<scene>\n<objects>\n" + object +
                                "\n</objects>\n<film width=\"4\" height=\"4\"/>\n"
                                "<camera><eye x=\"0\" y=\"0\" z=\"5\"/><target x=\"0\" y=\"0\" "
                                "z=\"0\"/><up x=\"0\" y=\"1\" z=\"0\"/></camera>\n</scene>";
        try {
            parse_scene(xml, "bad.xml", ".");
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    using Catch::Matchers::Contains;
    CHECK_THAT(
        error_of(
            R"(<cylinder radius="1" capped="true" phi_max="90"><base x="0" y="0" z="0"/><top x="0" y="1" z="0"/></cylinder>)"),
        Contains("bad.xml:3") && Contains("must be whole"));
    CHECK_THAT(error_of(R"(<torus major_radius="1" minor_radius="2"/>)"),
               Contains("bad.xml:3") && Contains("ring torus"));
    CHECK_THAT(error_of(R"(<csg op="union"><disk radius="1"/></csg>)"),
               Contains("bad.xml:3") && Contains("unknown element <disk>"));
    CHECK_THAT(error_of(R"(<csg op="xor"><sphere radius="1"/></csg>)"), Contains("op="));
    CHECK_THAT(
        error_of(R"(<csg op="union"><sphere radius="1"><material type="lambert"/></sphere></csg>)"),
        Contains("no material of its own"));
    CHECK_THAT(
        error_of(
            R"(<torus><material type="lambert"><emission r="1" g="1" b="1"/></material></torus>)"),
        Contains("cannot emit"));
    CHECK_THAT(
        error_of(
            R"(<csg op="intersection"><sphere radius="1"><center x="-5" y="0" z="0"/></sphere><sphere radius="1"><center x="5" y="0" z="0"/></sphere></csg>)"),
        Contains("empty"));
    CHECK_THAT(
        error_of(R"(<cone radius="1"><base x="0" y="0" z="0"/><apex x="0" y="0" z="0"/></cone>)"),
        Contains("must differ"));
    CHECK_THAT(
        error_of(R"(<disk radius="1"><transform><scale x="1" y="0" z="1"/></transform></disk>)"),
        Contains("scale factor of zero"));
}

TEST_CASE(
    "shapes: pbrt-v4 disks and cylinders are analytic, and object instances place them "
    "and curves",
    "[shapes][pbrt][fast]") {
    const Scene s = parse_pbrt_scene(R"(WorldBegin
ObjectBegin "post"
  Translate 0 0 1
  Shape "cylinder" "float radius" 0.5 "float zmin" 0 "float zmax" 2
  Shape "curve" "point3 P" [0 0 0  0 0 1  0 0 2  0 0 3] "float width" 0.1
ObjectEnd
AttributeBegin
  Translate 10 0 0
  ObjectInstance "post"
AttributeEnd
AttributeBegin
  Translate -10 0 0
  Scale 2 2 2
  ObjectInstance "post"
AttributeEnd
Shape "disk" "float radius" 3 "float height" -1
)",
                                     "inst.pbrt", ".");
    // The definition itself renders nothing; each instance its copy.
    REQUIRE(s.shapes.size() == 3);
    REQUIRE(s.curves.size() == 2);
    const Bounds3 a = s.shapes[0].bounds(), b = s.shapes[1].bounds();
    CHECK(a.center().x == Approx(10.f));
    CHECK(a.lo.z == Approx(1.f));
    CHECK(a.hi.z == Approx(3.f));
    CHECK(b.center().x == Approx(-10.f));
    CHECK(b.lo.z == Approx(2.f));
    CHECK(b.hi.z == Approx(6.f));
    CHECK(s.shapes[2].shapes()[0].type == ShapeType::Disk);
    CHECK(s.shapes[2].bounds().lo.z == Approx(-1.f));
    CHECK(s.curves[0].bounds().center().x == Approx(10.f).margin(0.2f));
    CHECK(s.curves[1].bounds().center().x == Approx(-10.f).margin(0.4f));
    CHECK(s.curves[1].segments[0].w0 == Approx(0.2f));
    // A ray down onto the disk meets it analytically at z = -1.
    const auto acc = make_intersector(s, AccelType::Bvh);
    TraceCounters c;
    Hit1 h;
    REQUIRE(acc->intersect1({2.5f, 0.5f, 5.f, 0.f, 0.f, -1.f, 0.f, kInfinity}, h, c));
    CHECK(h.t == Approx(6.f));
}

TEST_CASE("shapes: closed shapes bound media: an ink cylinder and a CSG tube absorb exp(-sigma d)",
          "[shapes][csg][media][render]") {
    // Under a white sky, seen along their axes through a window 0.1 wide: a capped cylinder
    // of height 2, and a cylinder of height 3 with a hollow of height 1 inside (a difference:
    // the rays leave and re-enter the ink through the subtracted solid's caps), 2 units of ink.
    auto transmittance = [](const std::string& object) {
        const std::string xml = R"(<scene>
  <lights><environment intensity="1"><color r="1" g="1" b="1"/></environment></lights>
  <media><medium name="ink"><sigma_a r="0.2" g="0.5" b="1"/></medium></media>
  <objects>)" + object + R"(</objects>
  <film width="4" height="4" size="0.025"/>
  <renderer type="volpath" spp="16" max_depth="10"/>
  <camera type="orthographic"><eye x="0" y="0" z="10"/><target x="0" y="0" z="0"/>
    <up x="0" y="1" z="0"/></camera>
</scene>)";
        TestScene s(parse_scene(xml, "ink.xml", "."));
        const RenderResult r = render_test(s, 16);
        RGB mean{0.f};
        for (const RGB& p : r.film.pixels) mean += p * (1.f / float(r.film.pixels.size()));
        return mean;
    };
    const RGB cyl = transmittance(
        R"(<cylinder radius="1" capped="true" medium_inside="ink"><base x="0" y="0" z="-1"/>
           <top x="0" y="0" z="1"/><material type="interface"/></cylinder>)");
    CHECK(cyl.r == Approx(std::exp(-0.4f)).epsilon(0.01));
    CHECK(cyl.g == Approx(std::exp(-1.f)).epsilon(0.01));
    CHECK(cyl.b == Approx(std::exp(-2.f)).epsilon(0.01));
    const RGB tube = transmittance(
        R"(<csg op="difference" medium_inside="ink">
             <cylinder radius="1"><base x="0" y="0" z="-1.5"/><top x="0" y="0" z="1.5"/></cylinder>
             <cylinder radius="0.5"><base x="0" y="0" z="-0.5"/><top x="0" y="0" z="0.5"/></cylinder>
             <material type="interface"/></csg>)");
    CHECK(tube.r == Approx(std::exp(-0.4f)).epsilon(0.01));
    CHECK(tube.g == Approx(std::exp(-1.f)).epsilon(0.01));
    CHECK(tube.b == Approx(std::exp(-2.f)).epsilon(0.01));
}
