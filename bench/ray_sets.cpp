#include "ray_sets.h"

#include <cmath>
#include <random>
#include <stdexcept>

#include "engine/scene/obj_loader.h"

namespace foton::bench {

namespace {

void add_quad(TriangleMesh& m, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    const uint32_t base = uint32_t(m.num_vertices());
    for (const Vec3& p : {a, b, c, d}) m.positions.insert(m.positions.end(), {p.x, p.y, p.z});
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

// A block standing on the floor: four top corners (counter-clockwise) extruded down to y = 0.
void add_block(TriangleMesh& m, const Vec3 top[4]) {
    add_quad(m, top[0], top[1], top[2], top[3]);
    for (int i = 0; i < 4; ++i) {
        const Vec3 a = top[i], b = top[(i + 1) % 4];
        add_quad(m, {a.x, 0.f, a.z}, {b.x, 0.f, b.z}, b, a);
    }
}

// The Cornell box of ../shared/refs/README.md with the two blocks of the original
// measurements instead of spheres (the kernels see triangles only), the light as a quad.
KernelScene cornell() {
    KernelScene s;
    s.name = "cornell";
    TriangleMesh& m = s.mesh;
    add_quad(m, {0, 0, 0}, {555, 0, 0}, {555, 0, 559}, {0, 0, 559});          // floor
    add_quad(m, {0, 555, 0}, {0, 555, 559}, {555, 555, 559}, {555, 555, 0});  // ceiling
    add_quad(m, {0, 0, 559}, {555, 0, 559}, {555, 555, 559}, {0, 555, 559});  // back
    add_quad(m, {555, 0, 0}, {555, 555, 0}, {555, 555, 559}, {555, 0, 559});  // red
    add_quad(m, {0, 0, 0}, {0, 0, 559}, {0, 555, 559}, {0, 555, 0});          // green
    add_quad(m, {212.5f, 554, 227}, {342.5f, 554, 227}, {342.5f, 554, 332}, {212.5f, 554, 332});
    const Vec3 short_block[4] = {{130, 165, 65}, {82, 165, 225}, {240, 165, 272}, {290, 165, 114}};
    const Vec3 tall_block[4] = {{423, 330, 247}, {265, 330, 296}, {314, 330, 456}, {472, 330, 406}};
    add_block(m, short_block);
    add_block(m, tall_block);
    s.eye = {278, 277.5f, -800};
    s.target = {278, 277.5f, 0};
    s.fov_deg = 39.3077f;
    s.light = {278, 548, 279.5f};
    return s;
}

KernelScene framed_mesh(const std::string& name, TriangleMesh mesh, const Bounds3& frame) {
    KernelScene s;
    s.name = name;
    s.mesh = std::move(mesh);
    const Vec3 c = frame.center();
    const float r = 0.5f * length(frame.diagonal());
    s.target = c;
    s.eye = c + normalize(Vec3{0.3f, 0.25f, 1.f}) * (2.8f * r);
    s.fov_deg = 45.f;
    s.light = c + Vec3{0.f, 2.f, 1.f} * (2.f * r);
    return s;
}

// The teapot on the floor of a bowl 200 teapots across and 20 high: the classic case where
// one uniform grid over the whole scene leaves the detailed object in a handful of cells.
KernelScene stadium(const std::string& shared) {
    TriangleMesh m = load_obj(shared + "/meshes/teapot.obj").mesh;
    const Bounds3 tb = m.bounds();
    const Vec3 c = tb.center();
    const float size = max_abs_component(tb.diagonal());
    const float R = 100.f * size, H = 20.f * size, y0 = tb.lo.y;
    const int segments = 96;
    for (int i = 0; i < segments; ++i) {
        const float a0 = 2.f * kPi * float(i) / segments, a1 = 2.f * kPi * float(i + 1) / segments;
        const Vec3 p0{c.x + R * std::cos(a0), y0, c.z + R * std::sin(a0)};
        const Vec3 p1{c.x + R * std::cos(a1), y0, c.z + R * std::sin(a1)};
        const uint32_t base = uint32_t(m.num_vertices());
        const Vec3 centre{c.x, y0, c.z};
        for (const Vec3& p : {centre, p1, p0})
            m.positions.insert(m.positions.end(), {p.x, p.y, p.z});
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
        // The stands rise outwards.
        const Vec3 q0 = centre + (p0 - centre) * 1.3f + Vec3{0, H, 0};
        const Vec3 q1 = centre + (p1 - centre) * 1.3f + Vec3{0, H, 0};
        add_quad(m, p0, p1, q1, q0);
    }
    return framed_mesh("stadium", std::move(m), tb);
}

}  // namespace

KernelScene load_kernel_scene(const std::string& name) {
    const std::string shared = std::string(FOTON_SOURCE_DIR) + "/../shared";
    if (name == "cornell") return cornell();
    if (name == "stadium") return stadium(shared);
    if (name == "bunny" || name == "dragon" || name == "teapot") {
        TriangleMesh m = load_obj(shared + "/meshes/" + name + ".obj").mesh;
        const Bounds3 b = m.bounds();
        return framed_mesh(name, std::move(m), b);
    }
    throw std::invalid_argument("unknown kernel scene '" + name + "'");
}

RaySets make_ray_sets(const KernelScene& s, int width, std::size_t surface_rays, uint32_t seed) {
    RaySets rs;
    rs.width = width;
    const Vec3 w = normalize(s.target - s.eye), u = normalize(cross(w, {0, 1, 0})), v = cross(u, w);
    const float half = std::tan(0.5f * s.fov_deg * kPi / 180.f);
    const std::size_t n = std::size_t(width) * std::size_t(width);
    rs.primary.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        // Morton order: x from the even bits of i, y from the odd ones.
        uint32_t x = 0, y = 0;
        for (int b = 0; b < 16; ++b) {
            x |= uint32_t((i >> (2 * b)) & 1u) << b;
            y |= uint32_t((i >> (2 * b + 1)) & 1u) << b;
        }
        const float px = (2.f * (float(x) + 0.5f) / float(width) - 1.f) * half;
        const float py = (1.f - 2.f * (float(y) + 0.5f) / float(width)) * half;
        const Vec3 d = normalize(w + u * px + v * py);
        rs.primary.push_back({s.eye.x, s.eye.y, s.eye.z, d.x, d.y, d.z, 0.f, kern::kInf});
    }

    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> U(0.f, 1.f);
    const TriangleMesh& m = s.mesh;
    const float eps = 1e-4f * length(m.bounds().diagonal());
    for (std::size_t i = 0; i < surface_rays; ++i) {
        // A uniformly chosen triangle (not area-weighted: the rays then follow the detail).
        Vec3 a, b, c;
        m.corners(uint32_t(rng() % m.num_triangles()), a, b, c);
        float s1 = U(rng), s2 = U(rng);
        if (s1 + s2 > 1.f) s1 = 1.f - s1, s2 = 1.f - s2;
        const Vec3 p = a + (b - a) * s1 + (c - a) * s2;
        const Vec3 nrm = normalize(cross(b - a, c - a));
        Vec3 t1, t2;
        orthonormal_basis(nrm, t1, t2);
        const float r = std::sqrt(U(rng)), phi = 2.f * kPi * U(rng);
        const float side = (i & 1) ? 1.f : -1.f;  // both sides of open scanned surfaces
        const Vec3 dir = t1 * (r * std::cos(phi)) + t2 * (r * std::sin(phi)) +
                         nrm * (side * std::sqrt(std::max(0.f, 1.f - r * r)));
        const Vec3 o = p + nrm * (side * eps);
        rs.diffuse.push_back({o.x, o.y, o.z, dir.x, dir.y, dir.z, 0.f, kern::kInf});
        const Vec3 to = s.light - o;
        const float dist = length(to);
        const Vec3 l = to / dist;
        rs.shadow.push_back({o.x, o.y, o.z, l.x, l.y, l.z, 0.f, dist});
    }
    return rs;
}

}  // namespace foton::bench
