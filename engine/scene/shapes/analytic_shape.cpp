#include "analytic_shape.h"

#include <algorithm>
#include <cmath>

#include "engine/core/polynomial.h"

namespace foton {

namespace {

constexpr double kLineEnd = HUGE_VAL;

double ddot3(const double* a, const double* b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// A piece of the line: [t0, t1] with the parts its ends lie on.
struct LineInterval {
    double t0, t1;
    uint8_t part0, part1;
};

// Where A t^2 + B t + C < 0 (the inside of a quadric crossed by the line), as up to two
// intervals (infinite ends where the quadric is open), all ends on `part`.
int quadric_inside(double A, double B, double C, uint8_t part, LineInterval* out) {
    if (A == 0.0) {
        if (B == 0.0) {
            if (C >= 0.0) return 0;
            out[0] = {-kLineEnd, kLineEnd, part, part};
            return 1;
        }
        const double r = -C / B;
        out[0] = B > 0.0 ? LineInterval{-kLineEnd, r, part, part}
                         : LineInterval{r, kLineEnd, part, part};
        return 1;
    }
    double roots[2];
    const double c[3] = {C, B, A};
    if (polynomial_roots(c, 2, -kLineEnd, kLineEnd, roots) < 2) {
        if (A > 0.0) return 0;
        out[0] = {-kLineEnd, kLineEnd, part, part};
        return 1;
    }
    if (A > 0.0) {
        out[0] = {roots[0], roots[1], part, part};
        return 1;
    }
    out[0] = {-kLineEnd, roots[0], part, part};
    out[1] = {roots[1], kLineEnd, part, part};
    return 2;
}

// The slab lo <= o + t d <= hi along one axis, its ends on part_lo and part_hi; false when
// the line misses it.
bool line_slab(double o, double d, double lo, double hi, uint8_t part_lo, uint8_t part_hi,
               LineInterval& out) {
    if (d == 0.0) {
        if (o < lo || o > hi) return false;
        out = {-kLineEnd, kLineEnd, part_lo, part_hi};
        return true;
    }
    const double a = (lo - o) / d, b = (hi - o) / d;
    out = a < b ? LineInterval{a, b, part_lo, part_hi} : LineInterval{b, a, part_hi, part_lo};
    return true;
}

// The intersection of two intervals, the ends taking the part of the one that bounds them.
bool clip_interval(const LineInterval& a, const LineInterval& b, LineInterval& out) {
    out = a;
    if (b.t0 > out.t0) out.t0 = b.t0, out.part0 = b.part0;
    if (b.t1 < out.t1) out.t1 = b.t1, out.part1 = b.part1;
    return out.t0 < out.t1;
}

bool within_phi(double x, double y, double phi_max) {
    if (phi_max >= 2.0 * kPi) return true;
    double phi = std::atan2(y, x);
    if (phi < 0.0) phi += 2.0 * kPi;
    return phi <= phi_max;
}

// The quadric of a cylinder's, cone's, paraboloid's or hyperboloid's side crossed by the
// line: A t^2 + B t + C, negative inside.
void side_quadric(const ShapePrimitive& s, const ShapeRay& r, double& A, double& B, double& C) {
    const double* o = r.o;
    const double* d = r.d;
    const double R = s.radius;
    A = d[0] * d[0] + d[1] * d[1];
    B = 2.0 * (o[0] * d[0] + o[1] * d[1]);
    C = o[0] * o[0] + o[1] * o[1] - R * R;
    const double H = s.height;
    if (s.type == ShapeType::Cone) {
        // x^2 + y^2 - k^2 (H - z)^2 with k = R / H.
        const double k = R / H, w = H - o[2];
        A -= k * k * d[2] * d[2];
        B += 2.0 * k * k * w * d[2];
        C = o[0] * o[0] + o[1] * o[1] - k * k * w * w;
    } else if (s.type == ShapeType::Paraboloid) {
        // x^2 + y^2 - (R^2 / H) z.
        const double k = R * R / H;
        B -= k * d[2];
        C = o[0] * o[0] + o[1] * o[1] - k * o[2];
    } else if (s.type == ShapeType::Hyperboloid) {
        // x^2 + y^2 - a^2 - (R^2 - a^2) w^2 with w = 2 z / H - 1 = wo + t wd along the ray.
        const double a = s.inner_radius, k = R * R - a * a;
        const double wo = 2.0 * o[2] / H - 1.0, wd = 2.0 * d[2] / H;
        A -= k * wd * wd;
        B -= 2.0 * k * wo * wd;
        C = o[0] * o[0] + o[1] * o[1] - a * a - k * wo * wo;
    }
}

bool quadric_side(ShapeType t) {
    return t == ShapeType::Cylinder || t == ShapeType::Cone || t == ShapeType::Paraboloid ||
           t == ShapeType::Hyperboloid;
}

int solid_intervals(const ShapePrimitive& s, const ShapeRay& r, LineInterval* out) {
    const double* o = r.o;
    const double* d = r.d;
    switch (s.type) {
        case ShapeType::Sphere: {
            const double R = s.radius;
            return quadric_inside(ddot3(d, d), 2.0 * ddot3(o, d), ddot3(o, o) - R * R, 0, out);
        }
        case ShapeType::Box: {
            LineInterval acc{-kLineEnd, kLineEnd, 0, 0}, ax;
            for (int a = 0; a < 3; ++a) {
                const double h = (&s.half.x)[a];
                if (!line_slab(o[a], d[a], -h, h, uint8_t(2 * a), uint8_t(2 * a + 1), ax) ||
                    !clip_interval(acc, ax, acc))
                    return 0;
            }
            out[0] = acc;
            return 1;
        }
        case ShapeType::Cylinder:
        case ShapeType::Cone:
        case ShapeType::Paraboloid:
        case ShapeType::Hyperboloid: {
            double A, B, C;
            side_quadric(s, r, A, B, C);
            LineInterval inside[2], z;
            const int n = quadric_inside(A, B, C, 0, inside);
            // The cone's top is its apex and the paraboloid's bottom its vertex: no caps.
            const uint8_t bottom = s.type == ShapeType::Paraboloid ? 0 : 1;
            const uint8_t top = s.type == ShapeType::Cone ? 0 : 2;
            if (!line_slab(o[2], d[2], 0.0, s.height, bottom, top, z)) return 0;
            int k = 0;
            for (int i = 0; i < n; ++i)
                if (clip_interval(inside[i], z, out[k])) ++k;
            return k;
        }
        case ShapeType::Torus: {
            // In s = (t - t_c) |d|, from the line's closest point to the centre: the quartic has no
            // cubic term and its roots lie within the torus' outer radius of that point.
            const double dd = ddot3(d, d), len = std::sqrt(dd);
            const double tc = -ddot3(o, d) / dd;
            const double p[3] = {o[0] + tc * d[0], o[1] + tc * d[1], o[2] + tc * d[2]};
            const double e[3] = {d[0] / len, d[1] / len, d[2] / len};
            const double R = s.radius, rr = s.minor_radius, outer = R + rr;
            const double p2 = ddot3(p, p);
            if (p2 >= outer * outer) return 0;
            const double reach = std::sqrt(outer * outer - p2) * (1.0 + 1e-9) + 1e-12 * outer;
            const double k = p2 + R * R - rr * rr;
            const double c[5] = {k * k - 4.0 * R * R * (p[0] * p[0] + p[1] * p[1]),
                                 -8.0 * R * R * (p[0] * e[0] + p[1] * e[1]),
                                 2.0 * k - 4.0 * R * R * (e[0] * e[0] + e[1] * e[1]), 0.0, 1.0};
            double roots[4];
            const int n = polynomial_roots(c, 4, -reach, reach, roots);
            // Inside where the quartic is negative: test between roots (an odd count from a
            // grazing ray still pairs up correctly).
            int m = 0;
            for (int i = 0; i + 1 < n; ++i)
                if (polynomial_value(c, 4, 0.5 * (roots[i] + roots[i + 1])) < 0.0)
                    out[m++] = {tc + roots[i] / len, tc + roots[i + 1] / len, 0, 0};
            return std::min(m, kMaxShapeSpans);
        }
        default:
            return 0;
    }
}

}  // namespace

const char* shape_type_name(ShapeType t) {
    switch (t) {
        case ShapeType::Disk:
            return "disk";
        case ShapeType::Cylinder:
            return "cylinder";
        case ShapeType::Cone:
            return "cone";
        case ShapeType::Torus:
            return "torus";
        case ShapeType::Sphere:
            return "sphere";
        case ShapeType::Box:
            return "box";
        case ShapeType::Paraboloid:
            return "paraboloid";
        case ShapeType::Hyperboloid:
            return "hyperboloid";
    }
    return "shape";
}

bool ShapePrimitive::place(const Affine& xf) {
    const Affine w = xf * to_world;
    if (!(std::fabs(w.determinant()) > 0.f)) return false;
    to_world = w;
    to_object = w.inverse();
    return true;
}

bool ShapePrimitive::solid() const {
    switch (type) {
        case ShapeType::Sphere:
        case ShapeType::Box:
        case ShapeType::Torus:
            return true;
        case ShapeType::Cylinder:
        case ShapeType::Cone:
        case ShapeType::Paraboloid:
        case ShapeType::Hyperboloid:
            return capped && phi_max >= 2.f * kPi;
        default:
            return false;
    }
}

Bounds3 ShapePrimitive::object_bounds() const {
    Bounds3 b;
    switch (type) {
        case ShapeType::Disk:
            b.extend(Vec3{-radius, -radius, 0.f}), b.extend(Vec3{radius, radius, 0.f});
            break;
        case ShapeType::Cylinder:
        case ShapeType::Cone:
        case ShapeType::Paraboloid:
        case ShapeType::Hyperboloid:
            b.extend(Vec3{-radius, -radius, 0.f}), b.extend(Vec3{radius, radius, height});
            break;
        case ShapeType::Torus: {
            const float o = radius + minor_radius;
            b.extend(Vec3{-o, -o, -minor_radius}), b.extend(Vec3{o, o, minor_radius});
            break;
        }
        case ShapeType::Sphere:
            b.extend(Vec3{-radius, -radius, -radius}), b.extend(Vec3{radius, radius, radius});
            break;
        case ShapeType::Box:
            b.extend(-half), b.extend(half);
            break;
    }
    return b;
}

Bounds3 ShapePrimitive::world_bounds() const {
    const Bounds3 b = object_bounds();
    Bounds3 w;
    for (int c = 0; c < 8; ++c)
        w.extend(to_world.point(
            {(c & 1) ? b.hi.x : b.lo.x, (c & 2) ? b.hi.y : b.lo.y, (c & 4) ? b.hi.z : b.lo.z}));
    return w;
}

ShapeRay to_object_space(const ShapePrimitive& s, const Vec3& o, const Vec3& d) {
    const auto& m = s.to_object.m;
    ShapeRay r;
    for (int i = 0; i < 3; ++i) {
        r.o[i] =
            double(m[i][0]) * o.x + double(m[i][1]) * o.y + double(m[i][2]) * o.z + double(m[i][3]);
        r.d[i] = double(m[i][0]) * d.x + double(m[i][1]) * d.y + double(m[i][2]) * d.z;
    }
    return r;
}

int shape_spans(const ShapePrimitive& s, const ShapeRay& r, ShapeSpan* out) {
    LineInterval iv[kMaxShapeSpans];
    const int n = solid_intervals(s, r, iv);
    for (int i = 0; i < n; ++i) out[i] = {iv[i].t0, iv[i].t1, iv[i].part0, iv[i].part1};
    return n;
}

int shape_crossings(const ShapePrimitive& s, const ShapeRay& r, ShapeCrossing* out) {
    if (s.solid()) {
        ShapeSpan spans[kMaxShapeSpans];
        const int n = shape_spans(s, r, spans);
        for (int i = 0; i < n; ++i) {
            out[2 * i] = {spans[i].t0, uint8_t(spans[i].part0)};
            out[2 * i + 1] = {spans[i].t1, uint8_t(spans[i].part1)};
        }
        return 2 * n;
    }
    const double* o = r.o;
    const double* d = r.d;
    int k = 0;
    auto keep = [&](double t, uint8_t part, bool on) {
        if (on) out[k++] = {t, part};
    };
    if (s.type == ShapeType::Disk) {
        if (d[2] == 0.0) return 0;
        const double t = -o[2] / d[2];
        const double x = o[0] + t * d[0], y = o[1] + t * d[1], rho2 = x * x + y * y;
        const double R = s.radius, ri = s.inner_radius;
        keep(t, 0, rho2 <= R * R && rho2 >= ri * ri && within_phi(x, y, s.phi_max));
        return k;
    }
    if (!quadric_side(s.type)) return 0;
    // An open side (uncapped, or cut in phi): the quadric's roots within its height and phi.
    double A, B, C, roots[2];
    side_quadric(s, r, A, B, C);
    const double c[3] = {C, B, A};
    const int n = polynomial_roots(c, 2, -kLineEnd, kLineEnd, roots);
    for (int i = 0; i < n; ++i) {
        const double t = roots[i], z = o[2] + t * d[2];
        keep(t, 0,
             z >= 0.0 && z <= s.height && within_phi(o[0] + t * d[0], o[1] + t * d[1], s.phi_max));
    }
    return k;
}

}  // namespace foton
