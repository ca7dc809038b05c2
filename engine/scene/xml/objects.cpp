// <objects>: meshes, spheres, quads and their transforms (analytic shapes: shapes.cpp).
#include "loader.h"

#include <filesystem>

#include "engine/core/input_file.h"
#include "engine/scene/mesh_file.h"

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

// A mesh file's parts under an object's placement. A file placed more than once is stored
// once, in its own space, and each placement is an instance of its meshes (one acceleration
// structure for all); a file placed once is moved into world space as before.
void Loader::place_mesh_file(const pugi::xml_node& o, const std::string& src,
                             const std::string& path, const Affine& xf, bool instanced) {
    // An object's <material> covers every part of the file; without one, the file's own
    // materials (OBJ's MTL, glTF's) apply, and a part without one is grey.
    const bool own = bool(o.child("material"));
    const uint32_t mat = own ? parse_material(o) : 0;
    const bool smooth = boolean(o, "smooth", true);
    if (instanced && !(std::fabs(xf.determinant()) > 0.f))
        fail(o, "the transform is singular (a file placed more than once is instanced)");
    auto [it, first] = mesh_files_.try_emplace(path);
    LoadedMeshFile& lf = it->second;
    if (first || !instanced) {
        lf = LoadedMeshFile{};
        try {
            lf.file = load_mesh_file(path);
        } catch (const InputError& e) {
            // Errors inside the file carry its own name and line; say which object read it.
            if (e.file() == path && e.line() > 0) throw;
            fail(o, std::string(e.what()));
        }
        if (lf.file.degenerate_skipped > 0)
            std::fprintf(stderr, "%s:%d: warning: %zu degenerate triangles skipped in %s\n",
                         name_.c_str(), line_of(o), lf.file.degenerate_skipped, src.c_str());
        scene_.skipped_degenerate += lf.file.degenerate_skipped;
        for (const std::string& note : lf.file.notes) scene_.warnings.push_back(note);
        lf.materials.assign(lf.file.materials.size(), -1);
    }
    if (own && !lf.file.materials.empty())
        scene_.warnings.push_back(name_ + ":" + std::to_string(line_of(o)) + ": the " +
                                  std::to_string(lf.file.materials.size()) + " materials of '" +
                                  src + "' are replaced by the object's <material>");
    if (lf.file.view && !scene_.model_view) {
        ModelView v = *lf.file.view;
        v.eye = xf.point(v.eye);
        v.target = xf.point(v.target);
        // An orthographic view's extent scales with the placement.
        v.half_height *= length(xf.vector(v.up));
        v.up = normalize(xf.vector(v.up));
        scene_.model_view = v;
    }
    // The file's lights, under this placement.
    for (PointLight p : lf.file.lights.points) {
        p.position = xf.point(p.position);
        scene_.lights.points.push_back(p);
    }
    for (SpotLight s : lf.file.lights.spots) {
        s.position = xf.point(s.position);
        s.direction = normalize(xf.vector(s.direction));
        scene_.lights.spots.push_back(s);
    }
    for (DirectionalLight d : lf.file.lights.directionals) {
        d.direction = normalize(xf.vector(d.direction));
        scene_.lights.directionals.push_back(d);
    }
    const std::string name = o.attribute("name") ? o.attribute("name").value() : src;
    for (std::size_t k = 0; k < lf.file.parts.size(); ++k) {
        MeshPart& part = lf.file.parts[k];
        uint32_t m = mat;
        if (!own) {
            if (part.material >= 0) {
                int& slot = lf.materials[std::size_t(part.material)];
                if (slot < 0)
                    slot = int(add_file_material(
                        scene_, lf.file.materials[std::size_t(part.material)], lf.file, images_));
                m = uint32_t(slot);
            } else {
                if (lf.grey < 0) {
                    Material g;
                    g.type = MaterialType::Generic;
                    g.name = "grey";
                    g.bsdf.add(Lobe::lambert(RGB{0.5f}));
                    scene_.materials.push_back(g);
                    lf.grey = int(scene_.materials.size() - 1);
                }
                m = uint32_t(lf.grey);
            }
        }
        if (instanced) {
            if (lf.meshes.size() <= k) {
                // Stored once with normals (a placement may still shade flat).
                part.mesh.name = name;
                if (part.mesh.normals.empty()) part.mesh.compute_smooth_normals();
                lf.meshes.push_back(uint32_t(scene_.meshes.size()));
                scene_.meshes.push_back(std::move(part.mesh));
            }
            scene_.add_instance(lf.meshes[k], xf, m, smooth);
            continue;
        }
        part.mesh.name = name;
        if (smooth && part.mesh.normals.empty()) part.mesh.compute_smooth_normals();
        if (!smooth) part.mesh.normals.clear();
        if (!xf.is_identity()) part.mesh.transform(xf);
        scene_.add_mesh(std::move(part.mesh), m, smooth);
    }
}

void Loader::parse_objects(const pugi::xml_node& n) {
    check(n, {},
          {"triangle_mesh", "sphere", "quad", "disk", "cylinder", "cone", "torus", "box",
           "paraboloid", "hyperboloid", "csg"});
    // How often each mesh file is placed: more than once, and its placements are instances.
    std::map<std::string, int> placements;
    for (const pugi::xml_node& o : n.children("triangle_mesh"))
        if (const char* src = o.attribute("src").value(); *src)
            ++placements[(std::filesystem::path(base_) / src).string()];
    for (const pugi::xml_node& o : n.children()) {
        if (o.type() != pugi::node_element) continue;
        const std::string_view kind = o.name();
        if (is_shape_element(kind)) {
            parse_shape_object(o);
        } else if (kind == "triangle_mesh") {
            check(o, {"src", "smooth", "name", "medium_inside", "medium_outside"},
                  {"material", "transform"});
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
            const std::size_t first = scene_.objects.size();
            place_mesh_file(o, src, path.string(), xf, placements[path.string()] > 1);
            const MediumInterface mi = medium_interface(o);
            for (std::size_t k = first; k < scene_.objects.size(); ++k)
                scene_.objects[k].media = mi;
        } else if (kind == "quad") {
            check(o, {"name", "medium_inside", "medium_outside"},
                  {"corner", "edge1", "edge2", "material", "transform"});
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
            const uint32_t id = scene_.add_mesh(std::move(q), parse_material(o), false);
            scene_.objects[id].media = medium_interface(o);
        } else {
            check(o, {"radius", "name", "medium_inside", "medium_outside"},
                  {"center", "material", "transform"});
            Sphere s;
            s.center = xyz_child(o, "center");
            s.radius = number(o, "radius");
            if (!(s.radius > 0.f)) fail(o, "sphere radius must be positive");
            if (!s.transform(parse_transform(o))) fail(o, "a sphere takes only uniform scaling");
            const uint32_t id = scene_.add_sphere(s, parse_material(o));
            scene_.objects[id].media = medium_interface(o);
        }
    }
}

}  // namespace foton::xml
