#pragma once
// Analytic shapes (the ray-tracing thesis' 6.4: disk, cylinder, cone, torus; with the sphere
// and the box as solids for CSG): each in a canonical object space, placed by any affine
// transform. Rays are taken into object space in double precision (the direction is not
// normalised, so t is the world ray's t) and met by the shape's own equation: a quadric's
// quadratic, the torus' quartic (core/polynomial.h), a box's slabs.
//
// Canonical forms (z is the axis):
//   disk      z = 0, inner_radius <= r <= radius, facing +z
//   cylinder  x^2 + y^2 = radius^2, 0 <= z <= height; caps: part 1 at z = 0, 2 at z = height
//   cone      x^2 + y^2 = (radius (1 - z / height))^2, 0 <= z <= height (apex at the top);
//             cap: part 1 at z = 0
//   paraboloid x^2 + y^2 = radius^2 z / height, 0 <= z <= height; cap: part 2 at the top
//   hyperboloid x^2 + y^2 = inner_radius^2 + (radius^2 - inner_radius^2) (2 z / height - 1)^2,
//             0 <= z <= height (one sheet: its waist of inner_radius halfway up); caps 1, 2
//   torus     (sqrt(x^2 + y^2) - radius)^2 + z^2 = minor_radius^2
//   sphere    x^2 + y^2 + z^2 = radius^2
//   box       |x| <= half.x, |y| <= half.y, |z| <= half.z; part 2 axis + (side > 0)
// Disk, cylinder, cone, paraboloid and hyperboloid may be cut to 0 <= phi <= phi_max (then
// they are open surfaces).
#include <cstdint>

#include "engine/core/math.h"
#include "engine/core/sampler.h"

namespace foton {

enum class ShapeType : uint8_t {
    Disk,
    Cylinder,
    Cone,
    Torus,
    Sphere,
    Box,
    Paraboloid,
    Hyperboloid
};
const char* shape_type_name(ShapeType t);

struct ShapePrimitive {
    ShapeType type = ShapeType::Sphere;
    float radius = 1.f;          // disk, cylinder, cone (at its base), torus (major), sphere
    float inner_radius = 0.f;    // disk
    float height = 1.f;          // cylinder, cone
    float minor_radius = 0.25f;  // torus
    Vec3 half{1.f, 1.f, 1.f};    // box
    float phi_max = 2.f * kPi;   // disk, cylinder, cone
    bool capped = false;  // cylinder, cone, paraboloid, hyperboloid: closed by disks (a solid)
    Affine to_world, to_object;

    // Places the shape (to_world = xf after the current placement); false, unchanged, when
    // xf is singular.
    bool place(const Affine& xf);
    // A solid bounds a volume (CSG takes only solids; media need one): sphere, box, torus,
    // and capped full cylinders, cones, paraboloids and hyperboloids.
    bool solid() const;
    Bounds3 object_bounds() const;
    Bounds3 world_bounds() const;  // the placed object box's eight corners
};

// A ray in a shape's object space.
struct ShapeRay {
    double o[3], d[3];
};
ShapeRay to_object_space(const ShapePrimitive& s, const Vec3& o, const Vec3& d);

// Where a ray's line crosses a surface: its t and the part crossed.
struct ShapeCrossing {
    double t;
    uint8_t part;
};
inline constexpr int kMaxShapeCrossings = 4;

// A stretch of the ray's line inside a solid, entering through part0, leaving through part1.
struct ShapeSpan {
    double t0, t1;
    uint32_t part0, part1;
};
inline constexpr int kMaxShapeSpans = 2;

// Every crossing of the whole line with the shape's surface, ascending t; returns the count.
// For a solid, crossings alternate entering and leaving.
int shape_crossings(const ShapePrimitive& s, const ShapeRay& r, ShapeCrossing* out);
// A solid's spans over the whole line (from its crossings), ascending; returns the count.
int shape_spans(const ShapePrimitive& s, const ShapeRay& r, ShapeSpan* out);

// The surface at an object-space point of a part: outward normal (unit), the
// parametrisation (u, v) in [0, 1]^2 and its partial derivatives, all in object space.
struct ShapeSurface {
    Vec3 n;
    Point2 uv;
    Vec3 dpdu, dpdv, dndu, dndv;
};
ShapeSurface shape_surface(const ShapePrimitive& s, uint8_t part, const Vec3& p);

}  // namespace foton
