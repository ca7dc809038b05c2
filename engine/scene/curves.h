#pragma once
// Curves (pbrt-v4's `curve` shape: hair, fur, grass): cubic Bézier segments of linearly varying
// width, intersected by kernels/curve_intersect.h through the CurveIntersector layer that every
// backend sits under. A curve set is one object; a hit's prim is its segment, u the parameter
// along the segment and v the position across the ribbon (kernels' CurveHit).
#include <cstdint>
#include <string>
#include <vector>

#include "engine/core/math.h"
#include "kernels/curve_intersect.h"

namespace foton {

using CurveForm = kern::CurveForm;

struct CurveSet {
    CurveForm form = CurveForm::Flat;
    std::vector<kern::CurveSegment> segments;
    std::size_t size() const { return segments.size(); }
    Bounds3 bounds() const;
    std::size_t memory_bytes() const { return segments.size() * sizeof(kern::CurveSegment); }
};

// What one curve statement holds, in world space: its control points by its basis and degree,
// split into cubic Bézier segments appended to `set`. Widths run linearly from width0 to width1
// over the whole curve; a ribbon takes one normal per segment end (`normals`, segments + 1).
// Throws std::invalid_argument on a count that fits no curve.
struct CurveInput {
    std::vector<Vec3> points;
    std::string basis = "bezier";  // or "bspline"
    int degree = 3;                // or 2
    float width0 = 1.f, width1 = 1.f;
    std::vector<Vec3> normals;
};
void append_curve(CurveSet& set, const CurveInput& in);

// The differential geometry of a curve hit (pbrt-v4's): dp/du along the segment; dp/dv across
// the ribbon, a width long: perpendicular to the tangent and the ray for flat and cylinder
// curves (a cylinder's then turned about the tangent by v, from -90 to 90 degrees, so its
// normal rounds across the width), along the ribbon's normal x tangent for ribbons; the
// normal dp/du x dp/dv, unit (either side: surface_at turns it to the viewer).
struct CurvePoint {
    Vec3 n, dpdu, dpdv;
    // The texture u: the segment's own parameter, as pbrt-v4 makes each segment of a curve
    // statement a curve of its own (u 0 to 1 along every segment).
    float u = 0.f;
    float width = 0.f;  // the curve's width at the hit
};
CurvePoint curve_point_at(const CurveSet& set, uint32_t segment, float u, float v, const Vec3& dir);

// The name of a curve form as pbrt writes it (flat, cylinder, ribbon).
const char* curve_form_name(CurveForm f);

}  // namespace foton
