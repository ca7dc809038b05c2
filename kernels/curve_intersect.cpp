#include "curve_intersect.h"

#include <algorithm>
#include <cmath>

namespace foton::kern {

namespace {

struct V3 {
    float x, y, z;
};
V3 operator+(V3 a, V3 b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
V3 operator-(V3 a, V3 b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
V3 operator*(V3 a, float s) {
    return {a.x * s, a.y * s, a.z * s};
}
float dot(V3 a, V3 b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
V3 load(const float p[3]) {
    return {p[0], p[1], p[2]};
}
float lerp(float t, float a, float b) {
    return a + (b - a) * t;
}

// Cubic Bézier by de Casteljau (stable for any t), with the derivative.
V3 bezier(const V3 cp[4], float t, V3* deriv) {
    const V3 a = cp[0] + (cp[1] - cp[0]) * t, b = cp[1] + (cp[2] - cp[1]) * t,
             c = cp[2] + (cp[3] - cp[2]) * t;
    const V3 d = a + (b - a) * t, e = b + (c - b) * t;
    if (deriv) *deriv = (e - d) * 3.f;
    return d + (e - d) * t;
}

// A point in the ray's frame.
V3 to_ray(const CurveRay& r, const float p[3]) {
    const V3 q = load(p) - load(r.o);
    return {dot(q, load(r.ex)), dot(q, load(r.ey)), dot(q, load(r.ez))};
}

V3 slerp_normal(const CurveSegment& s, float u) {
    const V3 n0 = load(s.n0), n1 = load(s.n1);
    const float c = std::clamp(dot(n0, n1), -1.f, 1.f);
    const float angle = std::acos(c);
    if (angle < 1e-5f) return n0;
    const float inv_sin = 1.f / std::sin(angle);
    return n0 * (std::sin((1.f - u) * angle) * inv_sin) + n1 * (std::sin(u * angle) * inv_sin);
}

struct Search {
    const CurveSegment& seg;
    bool ribbon;
    bool any;       // an occlusion query: the first hit ends it
    V3 dir;         // the ray's unit direction (ribbons narrow by their normal's angle to it)
    float inv_len;  // 1 / |d|
    float zmin, zmax;
    CurveHit hit;

    float width_at(float u) const {
        float w = lerp(u, seg.w0, seg.w1);
        if (ribbon) w *= std::fabs(dot(slerp_normal(seg, u), dir));
        return w;
    }

    // The chord of a flat-enough piece (u0..u1 of the segment).
    bool leaf(const V3 cp[4], float u0, float u1) {
        // The axis must lie between the perpendiculars to the end tangents, so neighbouring
        // pieces do not both claim a hit.
        if ((cp[1].y - cp[0].y) * -cp[0].y + cp[0].x * (cp[0].x - cp[1].x) < 0.f) return false;
        if ((cp[2].y - cp[3].y) * -cp[3].y + cp[3].x * (cp[3].x - cp[2].x) < 0.f) return false;
        const float sx = cp[3].x - cp[0].x, sy = cp[3].y - cp[0].y;
        const float denom = sx * sx + sy * sy;
        if (denom == 0.f) return false;
        const float w = (-cp[0].x * sx - cp[0].y * sy) / denom;
        const float u = std::clamp(lerp(w, u0, u1), u0, u1);
        const float width = width_at(u);
        V3 dpdw;
        const V3 pc = bezier(cp, std::clamp(w, 0.f, 1.f), &dpdw);
        const float d2 = pc.x * pc.x + pc.y * pc.y;
        if (d2 > width * width * 0.25f) return false;
        if (pc.z < zmin || pc.z > zmax) return false;
        const float dist = std::sqrt(d2);
        const float edge = dpdw.x * -pc.y + pc.x * dpdw.y;
        hit.t = pc.z * inv_len;
        hit.u = u;
        hit.v = edge > 0.f ? 0.5f + dist / width : 0.5f - dist / width;
        zmax = pc.z;  // later pieces must be closer
        return true;
    }

    bool recurse(const V3 cp[4], float u0, float u1, int depth) {
        if (depth == 0) return leaf(cp, u0, u1);
        const V3 m01 = (cp[0] + cp[1]) * 0.5f, m12 = (cp[1] + cp[2]) * 0.5f,
                 m23 = (cp[2] + cp[3]) * 0.5f;
        const V3 a = (m01 + m12) * 0.5f, b = (m12 + m23) * 0.5f, mid = (a + b) * 0.5f;
        const V3 halves[2][4] = {{cp[0], m01, a, mid}, {mid, b, m23, cp[3]}};
        const float um = 0.5f * (u0 + u1);
        const float ranges[2][2] = {{u0, um}, {um, u1}};
        bool any_hit = false;
        for (int h = 0; h < 2; ++h) {
            const V3* q = halves[h];
            const float r = 0.5f * std::max(lerp(ranges[h][0], seg.w0, seg.w1),
                                            lerp(ranges[h][1], seg.w0, seg.w1));
            float lo[3] = {q[0].x, q[0].y, q[0].z}, hi[3] = {q[0].x, q[0].y, q[0].z};
            for (int k = 1; k < 4; ++k) {
                const float c[3] = {q[k].x, q[k].y, q[k].z};
                for (int a3 = 0; a3 < 3; ++a3) {
                    lo[a3] = std::min(lo[a3], c[a3]);
                    hi[a3] = std::max(hi[a3], c[a3]);
                }
            }
            if (lo[0] - r > 0.f || hi[0] + r < 0.f || lo[1] - r > 0.f || hi[1] + r < 0.f ||
                lo[2] - r > zmax || hi[2] + r < zmin)
                continue;
            if (recurse(q, ranges[h][0], ranges[h][1], depth - 1)) {
                any_hit = true;
                if (any) return true;
            }
        }
        return any_hit;
    }
};

// Depth at which a piece lies within a twentieth of the width of its chord: halving a cubic
// quarters its second differences (L0), and a piece's distance from its chord is at most
// sqrt(2) 6 L0 / 8 (pbrt-v4's bound).
int subdivision_depth(const V3 cp[4], float max_width) {
    float l0 = 0.f;
    for (int i = 0; i < 2; ++i) {
        const V3 d = cp[i] - cp[i + 1] * 2.f + cp[i + 2];
        l0 = std::max({l0, std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)});
    }
    const float eps = max_width * 0.05f;
    if (!(l0 > 0.f) || !(eps > 0.f)) return 0;
    const float ratio = 1.41421356f * 6.f * l0 / (8.f * eps);
    if (!(ratio >= 1.f)) return 0;
    const int log2 = std::ilogb(ratio);  // floor(log2)
    return std::clamp(log2 / 2, 0, 10);
}

bool run(const CurveRay& ray, const CurveSegment& s, bool ribbon, bool any, float tmax,
         CurveHit& out) {
    if (!(ray.length > 0.f) || !std::isfinite(ray.length)) return false;
    V3 cp[4];
    for (int k = 0; k < 4; ++k) cp[k] = to_ray(ray, s.cp[k]);
    const float zmin = ray.tmin * ray.length, zmax = tmax * ray.length;
    // The whole segment's box first (the recursion tests its halves).
    const float r = 0.5f * std::max(s.w0, s.w1);
    float lo[3] = {cp[0].x, cp[0].y, cp[0].z}, hi[3] = {cp[0].x, cp[0].y, cp[0].z};
    for (int k = 1; k < 4; ++k) {
        const float c[3] = {cp[k].x, cp[k].y, cp[k].z};
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], c[a]);
            hi[a] = std::max(hi[a], c[a]);
        }
    }
    if (lo[0] - r > 0.f || hi[0] + r < 0.f || lo[1] - r > 0.f || hi[1] + r < 0.f ||
        lo[2] - r > zmax || hi[2] + r < zmin)
        return false;
    Search search{s, ribbon, any, load(ray.ez), 1.f / ray.length, zmin, zmax, {}};
    if (!search.recurse(cp, 0.f, 1.f, subdivision_depth(cp, std::max(s.w0, s.w1)))) return false;
    out = search.hit;
    return true;
}

}  // namespace

CurveRay::CurveRay(const Ray1& r) : tmin(r.tmin), tmax(r.tmax) {
    o[0] = r.ox, o[1] = r.oy, o[2] = r.oz;
    length = std::sqrt(r.dx * r.dx + r.dy * r.dy + r.dz * r.dz);
    const V3 z = V3{r.dx, r.dy, r.dz} * (1.f / length);
    // Any orthonormal pair around z (Duff et al. 2017).
    const float sign = std::copysign(1.f, z.z);
    const float a = -1.f / (sign + z.z), b = z.x * z.y * a;
    const V3 x{1.f + sign * z.x * z.x * a, sign * b, -sign * z.x}, y{b, sign + z.y * z.y * a, -z.y};
    ex[0] = x.x, ex[1] = x.y, ex[2] = x.z;
    ey[0] = y.x, ey[1] = y.y, ey[2] = y.z;
    ez[0] = z.x, ez[1] = z.y, ez[2] = z.z;
}

bool intersect_curve(const CurveRay& ray, const CurveSegment& s, bool ribbon, CurveHit& hit) {
    return run(ray, s, ribbon, false, std::min(ray.tmax, hit.t), hit);
}

bool intersect_curve(const Ray1& ray, const CurveSegment& s, bool ribbon, CurveHit& hit) {
    return intersect_curve(CurveRay(ray), s, ribbon, hit);
}

bool occluded_curve(const CurveRay& ray, const CurveSegment& s, bool ribbon) {
    CurveHit h;
    return run(ray, s, ribbon, true, ray.tmax, h);
}

bool occluded_curve(const Ray1& ray, const CurveSegment& s, bool ribbon) {
    return occluded_curve(CurveRay(ray), s, ribbon);
}

CurveSegment curve_part(const CurveSegment& s, float a, float b) {
    const V3 cp[4] = {load(s.cp[0]), load(s.cp[1]), load(s.cp[2]), load(s.cp[3])};
    // Split at b keeping [0, b], then that at a / b keeping the rest.
    auto split_left = [](const V3 c[4], float t, V3 out[4]) {
        const V3 a1 = c[0] + (c[1] - c[0]) * t, b1 = c[1] + (c[2] - c[1]) * t,
                 c1 = c[2] + (c[3] - c[2]) * t;
        const V3 a2 = a1 + (b1 - a1) * t, b2 = b1 + (c1 - b1) * t;
        out[0] = c[0], out[1] = a1, out[2] = a2, out[3] = a2 + (b2 - a2) * t;
    };
    auto split_right = [](const V3 c[4], float t, V3 out[4]) {
        const V3 a1 = c[0] + (c[1] - c[0]) * t, b1 = c[1] + (c[2] - c[1]) * t,
                 c1 = c[2] + (c[3] - c[2]) * t;
        const V3 a2 = a1 + (b1 - a1) * t, b2 = b1 + (c1 - b1) * t;
        out[0] = a2 + (b2 - a2) * t, out[1] = b2, out[2] = c1, out[3] = c[3];
    };
    V3 left[4], part[4];
    split_left(cp, b, left);
    if (b > 0.f) {
        split_right(left, a / b, part);
    } else {
        for (int k = 0; k < 4; ++k) part[k] = left[k];
    }
    CurveSegment out = s;
    for (int k = 0; k < 4; ++k) {
        out.cp[k][0] = part[k].x;
        out.cp[k][1] = part[k].y;
        out.cp[k][2] = part[k].z;
    }
    out.w0 = lerp(a, s.w0, s.w1);
    out.w1 = lerp(b, s.w0, s.w1);
    const V3 n0 = slerp_normal(s, a), n1 = slerp_normal(s, b);
    out.n0[0] = n0.x, out.n0[1] = n0.y, out.n0[2] = n0.z;
    out.n1[0] = n1.x, out.n1[1] = n1.y, out.n1[2] = n1.z;
    return out;
}

void curve_bounds(const CurveSegment& s, float lo[3], float hi[3]) {
    const float r = 0.5f * std::max(s.w0, s.w1);
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::min({s.cp[0][a], s.cp[1][a], s.cp[2][a], s.cp[3][a]}) - r;
        hi[a] = std::max({s.cp[0][a], s.cp[1][a], s.cp[2][a], s.cp[3][a]}) + r;
    }
}

void curve_point(const CurveSegment& s, float u, float p[3], float dpdu[3]) {
    const V3 cp[4] = {load(s.cp[0]), load(s.cp[1]), load(s.cp[2]), load(s.cp[3])};
    V3 d;
    const V3 q = bezier(cp, u, &d);
    p[0] = q.x, p[1] = q.y, p[2] = q.z;
    dpdu[0] = d.x, dpdu[1] = d.y, dpdu[2] = d.z;
}

void curve_ribbon_normal(const CurveSegment& s, float u, float n[3]) {
    const V3 q = slerp_normal(s, u);
    n[0] = q.x, n[1] = q.y, n[2] = q.z;
}

float curve_reference(const Ray1& ray, const CurveSegment& s, bool ribbon, int samples,
                      CurveHit& hit) {
    const CurveRay f(ray);
    V3 cp[4];
    for (int k = 0; k < 4; ++k) cp[k] = to_ray(f, s.cp[k]);
    auto width = [&](double u) {
        float w = lerp(float(u), s.w0, s.w1);
        if (ribbon) w *= std::fabs(dot(slerp_normal(s, float(u)), load(f.ez)));
        return double(w);
    };
    // Distance from the axis minus half the width: negative inside the ribbon.
    auto gap = [&](double u) {
        const V3 p = bezier(cp, float(u), nullptr);
        return std::sqrt(double(p.x) * p.x + double(p.y) * p.y) - 0.5 * width(u);
    };
    // The ribbon's cross-section at u is the line through B(u) perpendicular to the projected
    // tangent: the axis lies on it where B(u) . B'(u) = 0 seen end-on (a closest or, inside a
    // tight bend, a farthest point). Every such u, bracketed by a sign change and bisected.
    auto slope = [&](double u) {
        V3 dp;
        const V3 p = bezier(cp, float(u), &dp);
        return double(p.x) * dp.x + double(p.y) * dp.y;
    };
    float best_margin = -kInf;
    bool found = false;
    auto consider = [&](double um) {
        const float margin = float(-gap(um));
        V3 dp;
        const V3 p = bezier(cp, float(um), &dp);
        const float t = p.z / f.length;
        if (margin >= 0.f && t >= ray.tmin && t <= ray.tmax && (!found || t < hit.t)) {
            const float w = float(width(um));
            const float dist = std::sqrt(p.x * p.x + p.y * p.y);
            hit.t = t;
            hit.u = float(um);
            hit.v = dp.x * -p.y + p.x * dp.y > 0.f ? 0.5f + dist / w : 0.5f - dist / w;
            found = true;
            best_margin = margin;
        } else if (!found) {
            best_margin = std::max(best_margin, margin);
        }
    };
    const double du = 1.0 / double(samples);
    for (int k = 0; k < samples; ++k) {
        double a = double(k) * du, b = a + du;
        double fa = slope(a);
        if ((fa > 0.0) == (slope(b) > 0.0)) continue;
        for (int it = 0; it < 50; ++it) {
            const double m = 0.5 * (a + b);
            const double fm = slope(m);
            if ((fm > 0.0) == (fa > 0.0)) {
                a = m;
                fa = fm;
            } else {
                b = m;
            }
        }
        consider(0.5 * (a + b));
    }
    return best_margin;
}

}  // namespace foton::kern
