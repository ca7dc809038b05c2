// Shape and ObjectInstance: triangle and bilinear meshes, PLY meshes and spheres, placed in
// world space with pbrt-v4's orientation rules (the side an area light emits from and a
// dielectric's outside). Object instances are copies of their prototype's geometry.
#include <cmath>
#include <filesystem>

#include "engine/core/input_file.h"
#include "engine/scene/ply_reader.h"
#include "importer.h"

namespace foton::pbrt {

namespace {

// pbrt's geometric normal follows the winding, except that it faces the shading normals
// where the mesh has them: turn each triangle that way.
void orient_by_normals(TriangleMesh& m) {
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        Vec3 p0, p1, p2;
        m.corners(uint32_t(t), p0, p1, p2);
        const Vec3 ns = m.vertex_normal(m.indices[3 * t]) + m.vertex_normal(m.indices[3 * t + 1]) +
                        m.vertex_normal(m.indices[3 * t + 2]);
        if (dot(cross(p1 - p0, p2 - p0), ns) < 0.f)
            std::swap(m.indices[3 * t + 1], m.indices[3 * t + 2]);
    }
}

}  // namespace

void Importer::shape(const Token& t, const std::string& type, const ParamList& p) {
    const std::string what = "Shape \"" + type + "\"";
    if (p.has("alpha")) fail(t, what + ": alpha cut-outs are not supported");
    if (type == "sphere") {
        const float radius = p.real("radius", 1.f);
        if (!(radius > 0.f)) fail(t, "sphere radius must be positive");
        if (p.real("zmin", -radius) > -radius || p.real("zmax", radius) < radius ||
            p.real("phimax", 360.f) < 360.f)
            fail(t, "partial spheres (zmin, zmax, phimax) are not supported");
        const Bsdf& b = materials_[gs_.material].bsdf;
        bool refracts = false;
        for (int i = 0; i < b.size(); ++i) refracts |= b.lobe(i).type == LobeType::Dielectric;
        if (gs_.reverse && (gs_.area.id >= 0 || refracts))
            fail(t, "ReverseOrientation on an emitting or refracting sphere is not supported");
        Sphere s;
        s.center = {0, 0, 0};
        s.radius = radius;
        warn_unused(p, what);
        count("Shape " + type);
        add_sphere(s, t);
        return;
    }
    TriangleMesh m;
    m.name = type;
    std::vector<Vec3> normals;
    if (type == "trianglemesh" || type == "bilinearmesh") {
        const std::vector<Vec3> P = p.triples("P");
        std::vector<int> idx = p.integers("indices");
        if (P.empty()) fail(t, what + " needs \"point3 P\"");
        const std::size_t corners = type == "trianglemesh" ? 3 : 4;
        if (idx.empty() && P.size() == corners)
            for (std::size_t i = 0; i < corners; ++i) idx.push_back(int(i));
        if (idx.empty() || idx.size() % corners != 0)
            fail(t, what + ": \"integer indices\" must hold " + std::to_string(corners) + " per " +
                        (corners == 3 ? "triangle" : "patch"));
        for (int i : idx)
            if (i < 0 || std::size_t(i) >= P.size())
                fail(t, what + ": index " + std::to_string(i) + " outside the " +
                            std::to_string(P.size()) + " points");
        for (const Vec3& v : P) m.positions.insert(m.positions.end(), {v.x, v.y, v.z});
        normals = p.triples("N");
        const std::vector<float> uv = p.pairs("uv");
        if (!normals.empty() && normals.size() != P.size())
            fail(t, what + ": N must have one normal per point");
        if (!uv.empty() && uv.size() != 2 * P.size())
            fail(t, what + ": uv must have one pair per point");
        m.uvs = uv;
        if (corners == 3) {
            m.indices.assign(idx.begin(), idx.end());
        } else {
            // A bilinear patch p00 p10 p01 p11 as two triangles: exact when it is planar.
            bool curved = false;
            for (std::size_t q = 0; q < idx.size(); q += 4) {
                const uint32_t a = uint32_t(idx[q]), b = uint32_t(idx[q + 1]),
                               c = uint32_t(idx[q + 2]), d = uint32_t(idx[q + 3]);
                m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
                const Vec3 n = cross(P[b] - P[a], P[c] - P[a]);
                const float off = std::fabs(dot(P[d] - P[a], n)) / std::max(length(n), 1e-30f);
                if (off > 1e-4f * (length(P[d] - P[a]) + 1e-30f)) curved = true;
            }
            if (curved)
                warn(file(), t.line,
                     what +
                         ": non-planar bilinear patches are rendered as two "
                         "triangles each");
        }
        if (p.has("S")) warn(file(), t.line, what + ": tangents S ignored");
        if (p.has("faceIndices")) p.integers("faceIndices");
    } else if (type == "plymesh") {
        const std::string rel = p.text("filename", "");
        if (rel.empty()) fail(t, what + " needs \"string filename\"");
        if (p.has("displacement")) fail(t, what + ": displacement is not supported");
        const std::filesystem::path path = std::filesystem::path(rel).is_absolute()
                                               ? std::filesystem::path(rel)
                                               : std::filesystem::path(base_) / rel;
        const std::string problem = input_file_problem(path.string(), kMaxMeshFileBytes);
        if (!problem.empty())
            fail(t, (problem == "not found" ? std::string("mesh file not found")
                                            : "cannot read mesh file (" + problem + ")") +
                        ": '" + rel + "' (looked for " + path.string() + ")");
        if (path.extension() == ".gz") fail(t, "compressed PLY files (.ply.gz) are not supported");
        m = load_ply(path.string());
        m.name = rel;
        for (std::size_t i = 0; i < m.normals.size(); i += 3)
            normals.push_back({m.normals[i], m.normals[i + 1], m.normals[i + 2]});
        for (const char* ignored : {"edgelength"}) p.has(ignored);
    } else {
        fail(t, "unsupported shape '" + type + "' (trianglemesh, plymesh, bilinearmesh, sphere)");
    }
    m.normals.clear();
    for (const Vec3& n : normals) {
        if (length_squared(n) == 0.f) fail(t, what + ": a zero-length normal");
        const Vec3 u = normalize(n);
        m.normals.insert(m.normals.end(), {u.x, u.y, u.z});
    }
    m.transform(gs_.ctm);
    if (!m.normals.empty()) {
        if (gs_.reverse)
            for (float& c : m.normals) c = -c;
        orient_by_normals(m);
    } else if (gs_.reverse) {
        for (std::size_t i = 0; i < m.num_triangles(); ++i)
            std::swap(m.indices[3 * i + 1], m.indices[3 * i + 2]);
    }
    warn_unused(p, what);
    count("Shape " + type);
    const bool smooth = !m.normals.empty();
    add_mesh(std::move(m), smooth, t);
}

void Importer::add_mesh(TriangleMesh mesh, bool smooth, const Token&) {
    const uint32_t mat = scene_material(gs_);
    if (proto_) {
        proto_->meshes.push_back(std::move(mesh));
        proto_->mesh_materials.push_back(mat);
        proto_->mesh_smooth.push_back(smooth);
        return;
    }
    Object o;
    o.kind = ObjectKind::Mesh;
    o.index = uint32_t(scene_.meshes.size());
    o.material = mat;
    o.smooth = smooth;
    scene_.meshes.push_back(std::move(mesh));
    scene_.objects.push_back(o);
}

namespace {

// A sphere under `xf`, which must scale uniformly.
bool place_sphere(const Affine& xf, Sphere& s) {
    const float sx = length(xf.vector({1, 0, 0})), sy = length(xf.vector({0, 1, 0})),
                sz = length(xf.vector({0, 0, 1}));
    if (std::fabs(sx - sy) > 1e-5f * sx || std::fabs(sx - sz) > 1e-5f * sx) return false;
    s.center = xf.point(s.center);
    s.radius *= sx;
    return true;
}

}  // namespace

void Importer::add_sphere(const Sphere& sphere, const Token& t) {
    Sphere s = sphere;
    if (!place_sphere(gs_.ctm, s)) fail(t, "a sphere takes only uniform scaling");
    const uint32_t mat = scene_material(gs_);
    if (proto_) {
        proto_->spheres.push_back(s);
        proto_->sphere_materials.push_back(mat);
        return;
    }
    Object o;
    o.kind = ObjectKind::Sphere;
    o.index = uint32_t(scene_.spheres.size());
    o.material = mat;
    scene_.spheres.push_back(s);
    scene_.objects.push_back(o);
}

void Importer::object_instance(const Token& t, const std::string& name) {
    if (!defining_.empty()) fail(t, "ObjectInstance inside an object definition");
    const auto it = prototypes_.find(name);
    if (it == prototypes_.end()) fail(t, "unknown object '" + name + "'");
    const Prototype& pr = it->second;
    for (std::size_t i = 0; i < pr.meshes.size(); ++i) {
        TriangleMesh m = pr.meshes[i];
        m.transform(gs_.ctm);
        Object o;
        o.kind = ObjectKind::Mesh;
        o.index = uint32_t(scene_.meshes.size());
        o.material = pr.mesh_materials[i];
        o.smooth = pr.mesh_smooth[i];
        scene_.meshes.push_back(std::move(m));
        scene_.objects.push_back(o);
    }
    for (std::size_t i = 0; i < pr.spheres.size(); ++i) {
        Sphere s = pr.spheres[i];
        if (!place_sphere(gs_.ctm, s))
            fail(t, "an instance of a sphere takes only uniform scaling");
        Object o;
        o.kind = ObjectKind::Sphere;
        o.index = uint32_t(scene_.spheres.size());
        o.material = pr.sphere_materials[i];
        scene_.spheres.push_back(s);
        scene_.objects.push_back(o);
    }
    count("ObjectInstance (copied into the scene)");
}

}  // namespace foton::pbrt
