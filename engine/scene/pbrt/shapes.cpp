// Shape and ObjectInstance: triangle and bilinear meshes, PLY meshes, Loop subdivision
// surfaces, spheres, analytic (or, where needed, tessellated) disks and cylinders (curves:
// curves.cpp), placed in
// world space with pbrt-v4's orientation rules (the side an area light emits from and a
// dielectric's outside). Object instances share their prototype's meshes (placed by the
// instance's transform, one acceleration structure each); their spheres, analytic shapes and
// curves are copied and placed.
#include <cmath>
#include <filesystem>

#include "engine/core/input_file.h"
#include "engine/scene/mesh_shapes.h"
#include "engine/scene/ply_reader.h"
#include "importer.h"

namespace foton::pbrt {

namespace {

// Loop subdivision multiplies triangles by 4 a level; a file's levels stop where memory would.
constexpr int kMaxSubdivisionLevels = 10;
constexpr double kMaxSubdividedTriangles = 64e6;
// Segments of a disk's or cylinder's full circle (the polygon keeps the circle's area; the
// surface is within 0.02 % of the radius of the true one).
constexpr int kCircleSegments = 256;

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

bool Importer::refracts(uint32_t material) const {
    const Bsdf& b = materials_[material].bsdf;
    for (int i = 0; i < b.size(); ++i)
        if ((b.lobe(i).flags() & kTransmission) != 0) return true;
    return false;
}

// pbrt-v4's disk (radius, innerradius, height, phimax) or cylinder (radius, zmin, zmax,
// phimax) in the shape's object space: the canonical shape lifted to its height or zmin.
ShapePrimitive Importer::disk_or_cylinder(const Token& t, const std::string& type,
                                          const ParamList& p) {
    const std::string what = "Shape \"" + type + "\"";
    ShapePrimitive s;
    s.radius = p.real("radius", 1.f);
    s.phi_max = std::clamp(p.real("phimax", 360.f), 0.f, 360.f) * kPi / 180.f;
    if (!(s.radius > 0.f) || !(s.phi_max > 0.f))
        fail(t, what + ": radius and phimax must be positive");
    float lift;
    if (type == "disk") {
        s.type = ShapeType::Disk;
        s.inner_radius = p.real("innerradius", 0.f);
        if (!(s.inner_radius >= 0.f && s.inner_radius < s.radius))
            fail(t, what + ": innerradius must be in [0, radius)");
        lift = p.real("height", 0.f);
    } else {
        s.type = ShapeType::Cylinder;
        const float z0 = p.real("zmin", -1.f), z1 = p.real("zmax", 1.f);
        if (!(z1 != z0)) fail(t, what + ": zmin and zmax must differ");
        s.height = std::fabs(z1 - z0);
        lift = std::min(z0, z1);
    }
    s.place(Affine::translate({0.f, 0.f, lift}));
    return s;
}

void Importer::shape(const Token& t, const std::string& type, const ParamList& p) {
    const std::string what = "Shape \"" + type + "\"";
    // Alpha cut-outs: a constant in [0, 1] or a float texture (an RGBA image's alpha).
    shape_alpha_ = float_value(p, "alpha", 1.f, shape_alpha_texture_);
    if (shape_alpha_texture_ >= 0) shape_alpha_ = 1.f;
    if (!(shape_alpha_ >= 0.f && shape_alpha_ <= 1.f)) fail(t, what + ": alpha must be in [0, 1]");
    if (type == "curve") {
        curve(t, p);
        return;
    }
    if (type == "sphere") {
        const float radius = p.real("radius", 1.f);
        if (!(radius > 0.f)) fail(t, "sphere radius must be positive");
        if (p.real("zmin", -radius) > -radius || p.real("zmax", radius) < radius ||
            p.real("phimax", 360.f) < 360.f)
            fail(t, "partial spheres (zmin, zmax, phimax) are not supported");
        if (gs_.reverse && (gs_.area.id >= 0 || refracts(gs_.material)))
            fail(t, "ReverseOrientation on an emitting or refracting sphere is not supported");
        Sphere s;
        s.radius = radius;
        if (!s.transform(gs_.ctm)) fail(t, "a sphere takes only uniform scaling");
        warn_unused(p, what);
        count("Shape " + type);
        const uint32_t id = target().add_sphere(s, scene_material(gs_));
        target().objects[id].media = shape_media();
        return;
    }
    // Disks and cylinders are analytic unless an analytic shape cannot do what is asked:
    // emit (light sampling knows meshes and spheres), cut out, or bound a medium (they are
    // open surfaces). A reversed orientation only matters to those and to refraction.
    if ((type == "disk" || type == "cylinder") && gs_.area.id < 0 && shape_alpha_ >= 1.f &&
        shape_alpha_texture_ < 0 && !shape_media().transition() && !refracts(gs_.material)) {
        ShapePrimitive sp = disk_or_cylinder(t, type, p);
        if (!sp.place(gs_.ctm)) fail(t, what + ": the transform is singular");
        warn_unused(p, what);
        count("Shape " + type);
        target().add_shape(AnalyticShape(sp), scene_material(gs_));
        return;
    }
    TriangleMesh m;
    m.name = type;
    std::vector<Vec3> normals;
    std::string label = "Shape " + type;  // what `foton info` lists as imported
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
        const std::string path = input_path(t, "mesh file", rel, kMaxMeshFileBytes);
        try {
            m = load_ply(path);
        } catch (const InputError& e) {
            // The mesh's own problem (a corrupt .ply.gz, a bad header), at the Shape's line.
            fail(t, e.what());
        }
        m.name = rel;
        for (std::size_t i = 0; i < m.normals.size(); i += 3)
            normals.push_back({m.normals[i], m.normals[i + 1], m.normals[i + 2]});
        p.has("edgelength");  // only used with displacement, rejected above
    } else if (type == "loopsubdiv") {
        const std::vector<Vec3> P = p.triples("P");
        const std::vector<int> idx = p.integers("indices");
        const int levels = p.integer("levels", 3);
        if (levels < 0 || levels > kMaxSubdivisionLevels)
            fail(t,
                 what + ": levels must be in [0, " + std::to_string(kMaxSubdivisionLevels) + "]");
        if (P.empty() || idx.empty() || idx.size() % 3 != 0)
            fail(t, what + " needs \"point3 P\" and \"integer indices\" (three per triangle)");
        TriangleMesh control;
        for (const Vec3& v : P) control.positions.insert(control.positions.end(), {v.x, v.y, v.z});
        for (int i : idx) {
            if (i < 0 || std::size_t(i) >= P.size())
                fail(t, what + ": index " + std::to_string(i) + " outside the " +
                            std::to_string(P.size()) + " points");
            control.indices.push_back(uint32_t(i));
        }
        if (double(idx.size() / 3) * std::pow(4.0, levels) > kMaxSubdividedTriangles)
            fail(t, what + ": " + std::to_string(levels) + " levels would make over " +
                        std::to_string(uint64_t(kMaxSubdividedTriangles)) + " triangles");
        try {
            m = loop_subdivide(control, levels);
        } catch (const std::invalid_argument& e) {
            fail(t, what + ": " + e.what());
        }
        m.name = type;
        for (std::size_t i = 0; i < m.normals.size(); i += 3)
            normals.push_back({m.normals[i], m.normals[i + 1], m.normals[i + 2]});
    } else if (type == "disk" || type == "cylinder") {
        const ShapePrimitive sp = disk_or_cylinder(t, type, p);
        if (sp.type == ShapeType::Disk)
            m = tessellate_disk(0.f, sp.radius, sp.inner_radius, sp.phi_max, kCircleSegments);
        else
            m = tessellate_cylinder(sp.radius, 0.f, sp.height, sp.phi_max, kCircleSegments);
        m.transform(sp.to_world);  // its height or zmin, before the CTM below
        for (std::size_t i = 0; i < m.normals.size(); i += 3)
            normals.push_back({m.normals[i], m.normals[i + 1], m.normals[i + 2]});
        label = "Shape " + type + " (tessellated, " + std::to_string(kCircleSegments) +
                " segments a turn: it emits, cuts out or bounds a medium)";
    } else {
        fail(t, "unsupported shape '" + type +
                    "' (trianglemesh, plymesh, bilinearmesh, loopsubdiv, sphere, disk, cylinder, "
                    "curve)");
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
    count(label);
    const uint32_t id = target().add_mesh(std::move(m), scene_material(gs_), true);
    target().objects[id].media = shape_media();
}

void Importer::object_instance(const Token& t, const std::string& name) {
    if (!defining_.empty()) fail(t, "ObjectInstance inside an object definition");
    const auto it = prototypes_.find(name);
    if (it == prototypes_.end()) fail(t, "unknown object '" + name + "'");
    const Scene& pr = it->second;
    if (!(std::fabs(gs_.ctm.determinant()) > 0.f))
        fail(t, "ObjectInstance: the transform is singular");
    // The prototype's meshes enter the scene once, at the first instance.
    auto [shared, first] = instance_meshes_.try_emplace(name);
    if (first)
        for (const TriangleMesh& m : pr.meshes) {
            shared->second.push_back(uint32_t(scene_.meshes.size()));
            scene_.meshes.push_back(m);
        }
    for (const Object& o : pr.objects) {
        if (o.kind == ObjectKind::Mesh) {
            const uint32_t id =
                scene_.add_instance(shared->second[o.index], gs_.ctm, o.material, o.smooth);
            scene_.objects[id].media = o.media;
        } else if (o.kind == ObjectKind::Shape) {
            AnalyticShape sh = pr.shapes[o.index];
            if (!sh.place(gs_.ctm)) fail(t, "ObjectInstance: the transform is singular");
            scene_.objects[scene_.add_shape(std::move(sh), o.material)].media = o.media;
        } else if (o.kind == ObjectKind::Curves) {
            // Placed as Shape "curve" places them: points and normals by the transform,
            // widths by its mean scale.
            CurveSet set = pr.curves[o.index];
            const float scale = std::cbrt(std::fabs(gs_.ctm.determinant()));
            for (kern::CurveSegment& seg : set.segments) {
                for (auto& c : seg.cp) {
                    const Vec3 q = gs_.ctm.point({c[0], c[1], c[2]});
                    c[0] = q.x, c[1] = q.y, c[2] = q.z;
                }
                for (float* n : {seg.n0, seg.n1}) {
                    const Vec3 q = gs_.ctm.normal({n[0], n[1], n[2]});
                    n[0] = q.x, n[1] = q.y, n[2] = q.z;
                }
                seg.w0 *= scale;
                seg.w1 *= scale;
            }
            scene_.objects[scene_.add_curves(std::move(set), o.material)].media = o.media;
        } else {
            Sphere s = pr.spheres[o.index];
            if (!s.transform(gs_.ctm))
                fail(t, "an instance of a sphere takes only uniform scaling");
            scene_.objects[scene_.add_sphere(s, o.material)].media = o.media;
        }
    }
    count("ObjectInstance");
}

}  // namespace foton::pbrt
