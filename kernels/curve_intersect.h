#pragma once
// Rays against cubic Bézier curves of varying width: pbrt-v4's `curve` shape (flat, cylinder and
// ribbon) as a kernel of its own. A flat or cylinder curve is a ribbon that turns to face the
// ray (the two differ only in their shading normal, which is the engine's); a ribbon keeps the
// orientation its end normals give and narrows as it turns edge-on.
//
// The test (after Nakamaru and Ohno 2002, as pbrt-v4 does it; our code): the control points go
// to a frame whose z axis is the ray, so the ray is the z axis seen end-on; the curve is split in
// halves (de Casteljau) while the halves' control-point boxes, widened by half the width, contain
// the axis, to a depth at which a half deviates from its chord by at most a twentieth of the
// width; a half that deep is taken as its chord, and the ray hits it where the closest point of
// the chord to the axis lies within half the width there. So the hit is that of the true
// ray-facing ribbon up to the flatness bound.
#include <cstdint>

#include "ray1.h"

namespace foton::kern {

enum class CurveForm : uint8_t { Flat, Cylinder, Ribbon };

// One cubic Bézier segment: 72 bytes. Width varies linearly from w0 (u = 0) to w1 (u = 1);
// a ribbon's normal turns from n0 to n1 along the shorter arc (unit vectors; unused otherwise).
struct CurveSegment {
    float cp[4][3];
    float w0 = 1.f, w1 = 1.f;
    float n0[3] = {0.f, 0.f, 1.f}, n1[3] = {0.f, 0.f, 1.f};
};

// A hit: ray parameter t, u along the segment in [0, 1], v across it in [0, 1] (0.5 on the
// curve's centre line; which edge is 0 depends on the side the ray passes).
struct CurveHit {
    float t = kInf;
    float u = 0.f, v = 0.f;
};

// A ray with the frame the test projects into (z along its unit direction), made once per ray
// for all the segments it meets.
struct CurveRay {
    float o[3], ex[3], ey[3], ez[3];
    float length = 0.f;  // |d|: ray-space z is t * length
    float tmin = 0.f, tmax = kInf;
    CurveRay() = default;  // a slot to be assigned (a stream's lane)
    explicit CurveRay(const Ray1& r);
};

// The first hit of `ray` (within [tmin, min(tmax, hit.t)]) with the segment: true and `hit`
// updated when one is found. `ribbon`: the segment keeps its normals' orientation.
bool intersect_curve(const CurveRay& ray, const CurveSegment& s, bool ribbon, CurveHit& hit);
bool intersect_curve(const Ray1& ray, const CurveSegment& s, bool ribbon, CurveHit& hit);

// Whether the ray meets the segment within [tmin, tmax] (stops at the first hit found).
bool occluded_curve(const CurveRay& ray, const CurveSegment& s, bool ribbon);
bool occluded_curve(const Ray1& ray, const CurveSegment& s, bool ribbon);

// The part of s over u in [a, b] as a segment of its own (de Casteljau; widths and ribbon
// normals follow), so that its u runs 0..1 over what was a..b.
CurveSegment curve_part(const CurveSegment& s, float a, float b);

// Box of the segment: its control points' box widened by half its largest width (the curve
// lies in its control points' hull).
void curve_bounds(const CurveSegment& s, float lo[3], float hi[3]);

// The segment's point and derivative at u (cubic Bernstein form).
void curve_point(const CurveSegment& s, float u, float p[3], float dpdu[3]);

// The ribbon normal at u: n0 turned towards n1 by u of the angle between them.
void curve_ribbon_normal(const CurveSegment& s, float u, float n[3]);

// A brute-force reference of the same surface, for tests: the ray lies on the ribbon's
// cross-section at u where the curve seen end-on has B(u) . B'(u) = 0; every such u in [0, 1]
// (found by a sign change among `samples` steps, then bisection) is a candidate, a hit where
// the ray passes within half the width there (a ribbon's narrowed by its normal's angle to
// the ray) and inside [tmin, tmax]; the closest wins. Returns the
// margin, half the width minus the distance (negative: a miss), so tests can leave rays that
// graze an edge aside.
float curve_reference(const Ray1& ray, const CurveSegment& s, bool ribbon, int samples,
                      CurveHit& hit);

}  // namespace foton::kern
