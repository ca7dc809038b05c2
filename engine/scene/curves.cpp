#include "curves.h"

#include <cmath>
#include <stdexcept>

namespace foton {

namespace {

void store(kern::CurveSegment& s, const Vec3 b[4]) {
    for (int k = 0; k < 4; ++k) {
        s.cp[k][0] = b[k].x;
        s.cp[k][1] = b[k].y;
        s.cp[k][2] = b[k].z;
    }
}

// A quadratic Bézier as the cubic that traces it (degree elevation).
void elevate(const Vec3 q[3], Vec3 b[4]) {
    b[0] = q[0];
    b[1] = q[0] * (1.f / 3.f) + q[1] * (2.f / 3.f);
    b[2] = q[1] * (2.f / 3.f) + q[2] * (1.f / 3.f);
    b[3] = q[2];
}

}  // namespace

Bounds3 CurveSet::bounds() const {
    Bounds3 b;
    for (const kern::CurveSegment& s : segments) {
        float lo[3], hi[3];
        kern::curve_bounds(s, lo, hi);
        b.extend(Vec3{lo[0], lo[1], lo[2]});
        b.extend(Vec3{hi[0], hi[1], hi[2]});
    }
    return b;
}

void append_curve(CurveSet& set, const CurveInput& in) {
    const std::size_t n = in.points.size();
    const bool bspline = in.basis == "bspline";
    if (!bspline && in.basis != "bezier")
        throw std::invalid_argument("basis '" + in.basis + "' (bezier or bspline expected)");
    if (in.degree != 2 && in.degree != 3)
        throw std::invalid_argument("degree " + std::to_string(in.degree) + " (2 or 3 expected)");
    const std::size_t d = std::size_t(in.degree);
    // Bézier: d + 1 points, then d more per segment; B-spline: one more point per segment.
    std::size_t count = 0;
    if (bspline) {
        if (n < d + 1)
            throw std::invalid_argument("a degree " + std::to_string(d) +
                                        " B-spline needs at least " + std::to_string(d + 1) +
                                        " points, not " + std::to_string(n));
        count = n - d;
    } else {
        if (n < d + 1 || (n - 1) % d != 0)
            throw std::invalid_argument("a degree " + std::to_string(d) + " Bézier curve needs " +
                                        std::to_string(d) + " k + 1 points, not " +
                                        std::to_string(n));
        count = (n - 1) / d;
    }
    if (!in.normals.empty() && in.normals.size() != count + 1)
        throw std::invalid_argument("a ribbon of " + std::to_string(count) + " segments needs " +
                                    std::to_string(count + 1) + " normals, not " +
                                    std::to_string(in.normals.size()));
    if (!(in.width0 > 0.f && in.width1 > 0.f) || !std::isfinite(in.width0 + in.width1))
        throw std::invalid_argument("widths must be positive and finite");
    for (std::size_t i = 0; i < count; ++i) {
        Vec3 b[4];
        const Vec3* p = &in.points[bspline ? i : i * d];
        if (d == 3 && !bspline) {
            for (int k = 0; k < 4; ++k) b[k] = p[k];
        } else if (d == 3) {
            // Uniform cubic B-spline span to Bézier.
            b[0] = (p[0] + p[1] * 4.f + p[2]) * (1.f / 6.f);
            b[1] = (p[1] * 2.f + p[2]) * (1.f / 3.f);
            b[2] = (p[1] + p[2] * 2.f) * (1.f / 3.f);
            b[3] = (p[1] + p[2] * 4.f + p[3]) * (1.f / 6.f);
        } else if (!bspline) {
            elevate(p, b);
        } else {
            const Vec3 q[3] = {(p[0] + p[1]) * 0.5f, p[1], (p[1] + p[2]) * 0.5f};
            elevate(q, b);
        }
        kern::CurveSegment s;
        store(s, b);
        const float a0 = float(i) / float(count), a1 = float(i + 1) / float(count);
        s.w0 = in.width0 + (in.width1 - in.width0) * a0;
        s.w1 = in.width0 + (in.width1 - in.width0) * a1;
        if (!in.normals.empty()) {
            const Vec3 n0 = in.normals[i], n1 = in.normals[i + 1];
            if (length_squared(n0) == 0.f || length_squared(n1) == 0.f)
                throw std::invalid_argument("a zero-length ribbon normal");
            const Vec3 u0 = normalize(n0), u1 = normalize(n1);
            s.n0[0] = u0.x, s.n0[1] = u0.y, s.n0[2] = u0.z;
            s.n1[0] = u1.x, s.n1[1] = u1.y, s.n1[2] = u1.z;
        }
        set.segments.push_back(s);
    }
}

CurvePoint curve_point_at(const CurveSet& set, uint32_t segment, float u, float v,
                          const Vec3& dir) {
    const kern::CurveSegment& s = set.segments[segment];
    CurvePoint c;
    float p[3], d[3];
    kern::curve_point(s, u, p, d);
    c.dpdu = {d[0], d[1], d[2]};
    c.u = u;
    c.width = s.w0 + (s.w1 - s.w0) * u;
    Vec3 tangent = c.dpdu;
    if (!(length_squared(tangent) > 0.f)) {
        // A segment whose control points coincide at u: the chord's direction.
        tangent = Vec3{s.cp[3][0] - s.cp[0][0], s.cp[3][1] - s.cp[0][1], s.cp[3][2] - s.cp[0][2]};
        if (!(length_squared(tangent) > 0.f)) tangent = {1.f, 0.f, 0.f};
        c.dpdu = tangent;
    }
    const Vec3 k = normalize(tangent);
    Vec3 across;
    if (set.form == CurveForm::Ribbon) {
        float n[3];
        kern::curve_ribbon_normal(s, u, n);
        across = cross(Vec3{n[0], n[1], n[2]}, k);
    } else {
        across = cross(dir, k);
    }
    if (!(length_squared(across) > 1e-12f)) {
        // The ray (or the ribbon's normal) along the tangent: any perpendicular.
        Vec3 a, b;
        orthonormal_basis(k, a, b);
        across = a;
    }
    across = normalize(across);
    if (set.form == CurveForm::Cylinder) {
        // Turned by -theta about the tangent, theta from -90 to 90 degrees across the width.
        const float angle = -(-0.5f * kPi + kPi * v);
        across = across * std::cos(angle) + cross(k, across) * std::sin(angle);
    }
    c.dpdv = across * c.width;
    c.n = normalize(cross(k, across));
    return c;
}

const char* curve_form_name(CurveForm f) {
    switch (f) {
        case CurveForm::Flat:
            return "flat";
        case CurveForm::Cylinder:
            return "cylinder";
        case CurveForm::Ribbon:
            return "ribbon";
    }
    return "?";
}

}  // namespace foton
