// <disk>, <cylinder>, <cone>, <torus>, <box> and <csg> in <objects>: analytic shapes
// (scene/shapes/) placed by their own points and an optional <transform>.
#include <cmath>
#include <stdexcept>

#include "loader.h"

namespace foton::xml {

namespace {

// The placement taking the canonical z axis to `axis` (unit) at `origin`.
Affine axis_frame(const Vec3& origin, const Vec3& axis) {
    Vec3 u, v;
    orthonormal_basis(axis, u, v);
    Affine a;
    const Vec3 cols[4] = {u, v, axis, origin};
    for (int c = 0; c < 4; ++c) {
        a.m[0][c] = cols[c].x;
        a.m[1][c] = cols[c].y;
        a.m[2][c] = cols[c].z;
    }
    return a;
}

bool is_solid_element(std::string_view k) {
    return k == "sphere" || k == "box" || k == "cylinder" || k == "cone" || k == "torus" ||
           k == "paraboloid" || k == "hyperboloid" || k == "csg";
}

}  // namespace

bool Loader::is_shape_element(std::string_view k) {
    return k == "disk" || k == "cylinder" || k == "cone" || k == "torus" || k == "box" ||
           k == "paraboloid" || k == "hyperboloid" || k == "csg";
}

// An object takes a material, a name and media; a solid inside <csg> only its own
// attributes and a transform.
void Loader::check_shape(const pugi::xml_node& o, bool in_csg, const Names& own_attrs,
                         const Names& own_children) const {
    const Names object_attrs{"name", "medium_inside", "medium_outside"};
    for (const pugi::xml_attribute& a : o.attributes())
        if (!in(own_attrs, a.name()) && (in_csg || !in(object_attrs, a.name())))
            fail(o, std::string("unknown attribute '") + a.name() + "' on <" + o.name() + ">" +
                        (in_csg ? " in <csg>" : ""));
    for (const pugi::xml_node& c : o.children()) {
        if (c.type() != pugi::node_element) continue;
        const std::string_view cn = c.name();
        if (!in(own_children, c.name()) && cn != "transform" && (in_csg || cn != "material"))
            fail(c, std::string("unknown element <") + c.name() + "> in <" + o.name() + ">" +
                        (in_csg ? " (a solid in <csg> takes no material of its own)" : ""));
    }
}

float Loader::shape_phi_max(const pugi::xml_node& o) const {
    const float deg = number(o, "phi_max", 360.f);
    if (!(deg > 0.f && deg <= 360.f)) fail(o, "phi_max must be in (0, 360] degrees");
    return deg >= 360.f ? 2.f * kPi : deg * kPi / 180.f;
}

// A shape about an axis from a base point to a top one (cylinder, cone, paraboloid,
// hyperboloid) into s; returns the placement of its canonical frame.
Affine Loader::axial_shape(const pugi::xml_node& o, bool in_csg, ShapePrimitive& s) const {
    const std::string_view k = o.name();
    // From the base (a paraboloid's vertex: its <apex>) along the axis to the top (a
    // cone's <apex>).
    const char* base_name = k == "paraboloid" ? "apex" : "base";
    const char* tip = k == "cone" ? "apex" : "top";
    if (k == "cylinder")
        check_shape(o, in_csg, {"radius", "capped", "phi_max"}, {"base", "top"});
    else if (k == "cone")
        check_shape(o, in_csg, {"radius", "capped", "phi_max"}, {"base", "apex"});
    else if (k == "paraboloid")
        check_shape(o, in_csg, {"radius", "capped", "phi_max"}, {"apex", "top"});
    else
        check_shape(o, in_csg, {"radius", "waist_radius", "capped", "phi_max"}, {"base", "top"});
    s.type = k == "cylinder"     ? ShapeType::Cylinder
             : k == "cone"       ? ShapeType::Cone
             : k == "paraboloid" ? ShapeType::Paraboloid
                                 : ShapeType::Hyperboloid;
    s.radius = positive(o, "radius", 1.f);
    if (s.type == ShapeType::Hyperboloid) {
        s.inner_radius = positive(o, "waist_radius", 0.5f * s.radius);
        if (!(s.inner_radius <= s.radius))
            fail(o, "waist_radius must be at most radius (the ends' radius)");
    }
    s.capped = in_csg || boolean(o, "capped", false);
    s.phi_max = shape_phi_max(o);
    if (s.capped && s.phi_max < 2.f * kPi)
        fail(o, std::string("a capped ") + std::string(k) +
                    " must be whole (phi_max 360): its cut would be open");
    const Vec3 base = xyz_child(o, base_name), top = xyz_child(o, tip);
    const float h = length(top - base);
    if (!(h > 0.f)) fail(o, std::string("<") + base_name + "> and <" + tip + "> must differ");
    s.height = h;
    return axis_frame(base, (top - base) / h);
}

// One shape element, placed (its own points, then its <transform>). Inside a CSG tree only
// solids are allowed, and a <sphere> is one of them.
ShapePrimitive Loader::shape_primitive(const pugi::xml_node& o, bool in_csg) const {
    const std::string_view k = o.name();
    auto check = [&](const Names& own_attrs, const Names& own_children) {
        check_shape(o, in_csg, own_attrs, own_children);
    };
    ShapePrimitive s;
    Affine frame;
    if (k == "disk") {
        check({"radius", "inner_radius", "phi_max"}, {"center", "normal"});
        s.type = ShapeType::Disk;
        s.radius = positive(o, "radius", 1.f);
        s.inner_radius = non_negative(o, "inner_radius", 0.f);
        if (!(s.inner_radius < s.radius)) fail(o, "inner_radius must be less than radius");
        s.phi_max = shape_phi_max(o);
        const Vec3 c = o.child("center") ? xyz_child(o, "center") : Vec3{0.f, 0.f, 0.f};
        const Vec3 n = o.child("normal") ? direction(o, "normal") : Vec3{0.f, 0.f, 1.f};
        frame = axis_frame(c, n);
    } else if (k == "cylinder" || k == "cone" || k == "paraboloid" || k == "hyperboloid") {
        frame = axial_shape(o, in_csg, s);
    } else if (k == "torus") {
        check({"major_radius", "minor_radius"}, {"center", "axis"});
        s.type = ShapeType::Torus;
        s.radius = positive(o, "major_radius", 1.f);
        s.minor_radius = positive(o, "minor_radius", 0.25f);
        if (!(s.minor_radius < s.radius))
            fail(o, "minor_radius must be less than major_radius (a ring torus)");
        const Vec3 c = o.child("center") ? xyz_child(o, "center") : Vec3{0.f, 0.f, 0.f};
        const Vec3 a = o.child("axis") ? direction(o, "axis") : Vec3{0.f, 0.f, 1.f};
        frame = axis_frame(c, a);
    } else if (k == "box") {
        check({}, {"min", "max"});
        s.type = ShapeType::Box;
        const Vec3 lo = xyz_child(o, "min"), hi = xyz_child(o, "max");
        if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z))
            fail(o, "<min> must be below <max> on every axis");
        s.half = (hi - lo) * 0.5f;
        frame = Affine::translate((lo + hi) * 0.5f);
    } else if (k == "sphere" && in_csg) {
        check({"radius"}, {"center"});
        s.type = ShapeType::Sphere;
        s.radius = positive(o, "radius", 1.f);
        frame = Affine::translate(o.child("center") ? xyz_child(o, "center") : Vec3{0.f, 0.f, 0.f});
    } else {
        std::string what = "<";
        what += k;
        what += "> is not an analytic shape";
        fail(o, what);
    }
    if (!s.place(parse_transform(o) * frame)) fail(o, "the transform is singular");
    return s;
}

// A <csg> element's tree into `shape`: n-ary union and intersection fold left; a difference
// takes its first operand minus every other one. Returns the node.
uint32_t Loader::csg_node(const pugi::xml_node& o, const Affine& outer, AnalyticShape& shape,
                          int depth) const {
    const std::string_view k = o.name();
    if (k != "csg") {
        ShapePrimitive s = shape_primitive(o, true);
        if (!s.place(outer)) fail(o, "the transform is singular");
        try {
            return shape.leaf(s);
        } catch (const std::invalid_argument& e) {
            fail(o, e.what());
        }
    }
    if (depth > int(kMaxCsgSolids)) fail(o, "<csg> is nested too deeply");
    const bool top = depth == 0;
    check(o, top ? Names{"op", "name", "medium_inside", "medium_outside"} : Names{"op"},
          top ? Names{"material", "transform", "sphere", "box", "cylinder", "cone", "torus",
                      "paraboloid", "hyperboloid", "csg"}
              : Names{"transform", "sphere", "box", "cylinder", "cone", "torus", "paraboloid",
                      "hyperboloid", "csg"});
    const std::string op = o.attribute("op").value();
    CsgOp cop;
    if (op == "union")
        cop = CsgOp::Union;
    else if (op == "intersection")
        cop = CsgOp::Intersection;
    else if (op == "difference")
        cop = CsgOp::Difference;
    else
        fail(o, "<csg> needs op=\"union\", \"intersection\" or \"difference\" (got '" + op + "')");
    const Affine placed = outer * parse_transform(o);
    int64_t acc = -1;
    for (const pugi::xml_node& c : o.children()) {
        if (c.type() != pugi::node_element || !is_solid_element(c.name())) continue;
        const uint32_t node = csg_node(c, placed, shape, depth + 1);
        acc = acc < 0 ? int64_t(node) : int64_t(shape.combine(cop, uint32_t(acc), node));
    }
    if (acc < 0) fail(o, "<csg> needs at least one solid");
    return uint32_t(acc);
}

void Loader::parse_shape_object(const pugi::xml_node& o) {
    AnalyticShape shape;
    if (std::string_view(o.name()) == "csg") {
        csg_node(o, Affine{}, shape, 0);
        shape.finish();
    } else {
        shape = AnalyticShape(shape_primitive(o, false));
    }
    shape.name = o.attribute("name") ? o.attribute("name").value() : o.name();
    if (shape.bounds().empty()) fail(o, "the shape is empty (an intersection of disjoint solids)");
    const uint32_t m = parse_material(o);
    const Material& mat = scene_.materials[m];
    // Light sampling and cut-outs know meshes and spheres only: say so rather than render
    // the shape dark or whole.
    if (!mat.emission.is_black())
        fail(o, "an analytic shape cannot emit light (use a <triangle_mesh>, <quad> or <sphere>)");
    if (mat.cuts_out()) fail(o, "an analytic shape cannot take alpha cut-outs");
    const MediumInterface mi = medium_interface(o);
    if (mi.inside != mi.outside && !shape.solid())
        fail(o, "only a closed shape can bound a medium (cap the cylinder or cone)");
    const uint32_t id = scene_.add_shape(std::move(shape), m);
    scene_.objects[id].media = mi;
}

}  // namespace foton::xml
