#include "direct_control_variate.h"

#include <cmath>

namespace foton {

namespace {
struct PolygonVec {
    double x, y, z;
};
PolygonVec sub(const Vec3& a, const Vec3& b) {
    return {double(a.x) - b.x, double(a.y) - b.y, double(a.z) - b.z};
}
double dot(const PolygonVec& a, const PolygonVec& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
PolygonVec cross(const PolygonVec& a, const PolygonVec& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
PolygonVec lerp(const PolygonVec& a, const PolygonVec& b, double s) {
    return {a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), a.z + s * (b.z - a.z)};
}
}  // namespace

float polygon_cosine_integral(const Vec3* corners, int n, const Vec3& x, const Vec3& up) {
    // Corners relative to x, clipped to up . q >= 0 (one plane: at most one corner more).
    const PolygonVec u{up.x, up.y, up.z};
    PolygonVec clipped[5];
    int m = 0;
    for (int i = 0; i < n; ++i) {
        const PolygonVec p = sub(corners[i], x), q = sub(corners[(i + 1) % n], x);
        const double hp = dot(u, p), hq = dot(u, q);
        if (hp >= 0.0) clipped[m++] = p;
        if ((hp >= 0.0) != (hq >= 0.0) && m < 5) clipped[m++] = lerp(p, q, hp / (hp - hq));
    }
    if (m < 3) return 0.f;
    // Lambert: each edge, seen from x, sweeps an angle theta about the axis u_i x u_(i+1).
    double sum = 0.0;
    for (int i = 0; i < m; ++i) {
        const PolygonVec& a = clipped[i];
        const PolygonVec& b = clipped[(i + 1) % m];
        const PolygonVec c = cross(a, b);
        const double len = std::sqrt(dot(c, c));
        if (len == 0.0) {
            if (dot(a, a) == 0.0 || dot(b, b) == 0.0) return -1.f;  // x on a corner
            continue;  // an edge pointing at x: sweeps nothing
        }
        sum += std::atan2(len, dot(a, b)) * dot(u, c) / len;
    }
    return float(0.5 * std::fabs(sum));
}

bool emitter_cosine_integral(const LightSet& lights, const Scene& scene, uint32_t light,
                             uint32_t tri, const Vec3& x, const Vec3& up, float& integral) {
    const Emitter& e = lights.emitter(light);
    // Whether a face of normal n through q emits towards x (as sample_li's cos_l test).
    auto faces = [&](const Vec3& q, const Vec3& n) { return e.two_sided || dot(x - q, n) > 0.f; };
    integral = 0.f;
    if (e.type == EmitterType::Rect) {
        if (!faces(e.p, e.n)) return true;
        const Vec3 c[4] = {e.p, e.p + e.e1, e.p + e.e1 + e.e2, e.p + e.e2};
        integral = polygon_cosine_integral(c, 4, x, up);
        return integral >= 0.f;
    }
    if (e.type != EmitterType::Mesh) return false;
    const auto count = uint32_t(scene.meshes[e.mesh].num_triangles());
    if (tri == kWholeEmitter && count > kMaxPolygons) return false;
    const uint32_t first = tri == kWholeEmitter ? 0 : tri;
    const uint32_t last = tri == kWholeEmitter ? count : tri + 1;
    for (uint32_t t = first; t < last; ++t) {
        Vec3 c[3];
        scene.world_corners(e.geom, t, c[0], c[1], c[2]);
        if (!faces(c[0], cross(c[1] - c[0], c[2] - c[0]))) continue;
        const float part = polygon_cosine_integral(c, 3, x, up);
        if (part < 0.f) return false;
        integral += part;
    }
    return true;
}

RGB direct_control_term(const LightSet& lights, const Scene& scene, const ShadingPoint& v,
                        const LightPick& pick, const RGB& sample) {
    const SurfacePoint& sp = v.sp;
    RGB rho;

    // The closed form needs f constant over the hemisphere the light sample may take (a
    // Lambertian point) and the sample's cosine, taken about the shading normal, to be the
    // one about the geometric normal, whose hemisphere sample_light admits.
    if (!(pick.pmf > 0.f) || !v.m.bsdf.lambert_albedo(rho) || rho.is_black() ||
        dot(sp.ns, sp.ng) < 1.f - 1e-6f)
        return RGB{0.f};
    float integral;
    if (!emitter_cosine_integral(lights, scene, pick.light, pick.tri, sp.p, sp.ng, integral))
        return RGB{0.f};
    const BsdfContext ctx{sp.front_face, Transport::Radiance};
    const RGB f = v.m.bsdf.f_restricted(v.wo, v.frame.to_local(sp.ng), ctx, kDiffuse | kGlossy);
    return v.weight * f * lights.emitter(pick.light).value * (integral / pick.pmf) - sample;
}

}  // namespace foton
