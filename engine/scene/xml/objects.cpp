// <objects>: meshes, spheres, quads and their transforms.
#include "loader.h"

#include <filesystem>

#include "engine/core/input_file.h"
#include "engine/scene/obj_loader.h"

namespace foton::xml {

Affine Loader::parse_transform(const pugi::xml_node& object) const {
    Affine xf;
    const pugi::xml_node t = object.child("transform");
    if (!t) return xf;
    check(t, {}, {"translate", "scale", "rotate"});
    // Applied in document order: the first child acts first.
    for (const pugi::xml_node& c : t.children()) {
        if (c.type() != pugi::node_element) continue;
        const std::string_view k = c.name();
        if (k == "translate") {
            xf = Affine::translate(xyz(c)) * xf;
        } else if (k == "scale") {
            check(c, {"x", "y", "z", "s"}, {});
            Vec3 s;
            if (c.attribute("s")) {
                const float v = number(c, "s");
                s = {v, v, v};
            } else {
                s = {number(c, "x"), number(c, "y"), number(c, "z")};
            }
            if (s.x == 0.f || s.y == 0.f || s.z == 0.f) fail(c, "scale factor of zero");
            xf = Affine::scale(s) * xf;
        } else {
            check(c, {"x", "y", "z", "angle"}, {});
            const Vec3 axis{number(c, "x"), number(c, "y"), number(c, "z")};
            if (length_squared(axis) == 0.f) fail(c, "rotation axis is a zero vector");
            xf = Affine::rotate(axis, number(c, "angle")) * xf;
        }
    }
    return xf;
}

void Loader::parse_objects(const pugi::xml_node& n) {
    check(n, {}, {"triangle_mesh", "sphere", "quad"});
    for (const pugi::xml_node& o : n.children()) {
        if (o.type() != pugi::node_element) continue;
        const std::string_view kind = o.name();
        if (kind == "triangle_mesh") {
            check(o, {"src", "smooth", "name"}, {"material", "transform"});
            const std::string src = o.attribute("src").value();
            if (src.empty()) fail(o, "<triangle_mesh> needs attribute 'src'");
            const std::filesystem::path path = std::filesystem::path(base_) / src;
            // Any problem with the path (missing, a loop, too long, a pipe) at this line.
            const std::string problem = input_file_problem(path.string(), kMaxMeshFileBytes);
            if (!problem.empty())
                fail(o, (problem == "not found" ? std::string("mesh file not found")
                                                : "cannot read mesh file (" + problem + ")") +
                            ": '" + src + "' (looked for " + path.string() + ")");
            const Affine xf = parse_transform(o);
            const uint32_t mat = parse_material(o);
            ObjLoadResult r = load_obj(path.string());
            if (r.degenerate_skipped > 0)
                std::fprintf(stderr, "%s:%d: warning: %zu degenerate triangles skipped in %s\n",
                             name_.c_str(), line_of(o), r.degenerate_skipped, src.c_str());
            scene_.skipped_degenerate += r.degenerate_skipped;
            r.mesh.name = o.attribute("name") ? o.attribute("name").value() : src;
            const bool smooth = boolean(o, "smooth", true);
            if (smooth && !r.has_normals) r.mesh.compute_smooth_normals();
            if (!smooth) r.mesh.normals.clear();
            if (!xf.is_identity()) r.mesh.transform(xf);
            scene_.add_mesh(std::move(r.mesh), mat, smooth);
        } else if (kind == "quad") {
            check(o, {"name"}, {"corner", "edge1", "edge2", "material", "transform"});
            const Vec3 c = xyz_child(o, "corner"), e1 = xyz_child(o, "edge1"),
                       e2 = xyz_child(o, "edge2");
            if (length_squared(cross(e1, e2)) == 0.f) fail(o, "quad has zero area");
            const Affine xf = parse_transform(o);
            TriangleMesh q;
            q.name = o.attribute("name") ? o.attribute("name").value() : "quad";
            const Vec3 p[4] = {c, c + e1, c + e1 + e2, c + e2};
            for (const Vec3& v : p) q.positions.insert(q.positions.end(), {v.x, v.y, v.z});
            q.indices = {0, 1, 2, 0, 2, 3};
            if (!xf.is_identity()) q.transform(xf);
            scene_.add_mesh(std::move(q), parse_material(o), false);
        } else {
            check(o, {"radius", "name"}, {"center", "material", "transform"});
            Sphere s;
            s.center = xyz_child(o, "center");
            s.radius = number(o, "radius");
            if (!(s.radius > 0.f)) fail(o, "sphere radius must be positive");
            if (!s.transform(parse_transform(o))) fail(o, "a sphere takes only uniform scaling");
            scene_.add_sphere(s, parse_material(o));
        }
    }
}

}  // namespace foton::xml
