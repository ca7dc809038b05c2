#include "csg_shape.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace foton {

namespace {

// The inside stretches of a node's solid along the line, ascending and disjoint.
struct CsgSpans {
    ShapeSpan s[2 * kMaxCsgSolids];
    int n = 0;
};

bool csg_inside(CsgOp op, bool a, bool b) {
    switch (op) {
        case CsgOp::Union:
            return a || b;
        case CsgOp::Intersection:
            return a && b;
        default:
            return a && !b;  // Difference
    }
}

// Sweeps both lists' ends in order, keeping the stretches where `op` holds; each kept end
// takes the part of the end that caused it. Ties make empty stretches, which are dropped.
void combine_csg_spans(const CsgSpans& A, const CsgSpans& B, CsgOp op, CsgSpans& out) {
    out.n = 0;
    int i = 0, j = 0;
    bool in_a = false, in_b = false, in = false;
    double start = 0.0;
    uint32_t start_part = 0;
    for (;;) {
        const double ta = i < A.n ? (in_a ? A.s[i].t1 : A.s[i].t0) : HUGE_VAL;
        const double tb = j < B.n ? (in_b ? B.s[j].t1 : B.s[j].t0) : HUGE_VAL;
        if (i >= A.n && j >= B.n) break;
        double t;
        uint32_t part;
        if (ta <= tb) {
            t = ta;
            part = in_a ? A.s[i].part1 : A.s[i].part0;
            if (in_a) ++i;
            in_a = !in_a;
        } else {
            t = tb;
            part = in_b ? B.s[j].part1 : B.s[j].part0;
            if (in_b) ++j;
            in_b = !in_b;
        }
        const bool now = csg_inside(op, in_a, in_b);
        if (now && !in) {
            start = t;
            start_part = part;
        } else if (!now && in && t > start) {
            out.s[out.n++] = {start, t, start_part, part};
        }
        in = now;
    }
}

void eval_csg_node(const std::vector<CsgNode>& nodes, const std::vector<ShapePrimitive>& shapes,
                   uint32_t node, const Vec3& o, const Vec3& d, CsgSpans& out) {
    const CsgNode& n = nodes[node];
    if (n.op == CsgOp::Leaf) {
        const ShapePrimitive& s = shapes[n.a];
        ShapeSpan spans[kMaxShapeSpans];
        const int k = shape_spans(s, to_object_space(s, o, d), spans);
        out.n = 0;
        for (int i = 0; i < k; ++i)
            out.s[out.n++] = {spans[i].t0, spans[i].t1, shape_prim(n.a, spans[i].part0),
                              shape_prim(n.a, spans[i].part1)};
        return;
    }
    CsgSpans a, b;
    eval_csg_node(nodes, shapes, n.a, o, d, a);
    if (a.n == 0 && n.op != CsgOp::Union) {
        out.n = 0;
        return;
    }
    eval_csg_node(nodes, shapes, n.b, o, d, b);
    combine_csg_spans(a, b, n.op, out);
}

// A float t strictly inside (tmin, tmax).
bool t_within(double t, float tmin, float tmax, float& tf) {
    tf = float(t);
    return tf > tmin && tf < tmax;
}

}  // namespace

AnalyticShape::AnalyticShape(const ShapePrimitive& s) : shapes_{s}, inverted_{0} {
    bounds_ = s.world_bounds();
}

uint32_t AnalyticShape::leaf(const ShapePrimitive& s) {
    if (!s.solid())
        throw std::invalid_argument(std::string("a ") + shape_type_name(s.type) +
                                    " that is not a closed solid cannot be in CSG");
    if (shapes_.size() >= kMaxCsgSolids)
        throw std::invalid_argument("a CSG tree holds at most " + std::to_string(kMaxCsgSolids) +
                                    " solids");
    shapes_.push_back(s);
    nodes_.push_back({CsgOp::Leaf, uint32_t(shapes_.size() - 1), 0});
    return uint32_t(nodes_.size() - 1);
}

uint32_t AnalyticShape::combine(CsgOp op, uint32_t a, uint32_t b) {
    nodes_.push_back({op, a, b});
    return uint32_t(nodes_.size() - 1);
}

void AnalyticShape::finish() {
    if (nodes_.empty()) throw std::invalid_argument("a CSG tree needs at least one solid");
    inverted_.assign(shapes_.size(), 0);
    // Walk down from the root: the right operand of a difference turns its surfaces over;
    // each node's box bounds its solid (a difference's by its left operand's).
    struct Item {
        uint32_t node;
        uint8_t flip;
    };
    std::vector<Bounds3> box(nodes_.size());
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
        const CsgNode& n = nodes_[i];
        if (n.op == CsgOp::Leaf) {
            box[i] = shapes_[n.a].world_bounds();
        } else if (n.op == CsgOp::Union) {
            box[i] = box[n.a];
            box[i].extend(box[n.b]);
        } else if (n.op == CsgOp::Intersection) {
            box[i].lo = vmax(box[n.a].lo, box[n.b].lo);
            box[i].hi = vmin(box[n.a].hi, box[n.b].hi);
        } else {
            box[i] = box[n.a];
        }
    }
    bounds_ = box.back();
    std::vector<Item> stack{{uint32_t(nodes_.size() - 1), 0}};
    while (!stack.empty()) {
        const Item it = stack.back();
        stack.pop_back();
        const CsgNode& n = nodes_[it.node];
        if (n.op == CsgOp::Leaf) {
            inverted_[n.a] = it.flip;
            continue;
        }
        stack.push_back({n.a, it.flip});
        stack.push_back({n.b, uint8_t(n.op == CsgOp::Difference ? !it.flip : it.flip)});
    }
}

bool AnalyticShape::place(const Affine& xf) {
    if (!(std::fabs(xf.determinant()) > 0.f)) return false;
    for (ShapePrimitive& s : shapes_) s.place(xf);
    if (csg())
        finish();
    else
        bounds_ = shapes_[0].world_bounds();
    return true;
}

bool AnalyticShape::closest(const Vec3& o, const Vec3& d, float tmin, float tmax, float& t,
                            uint32_t& prim) const {
    float tf;
    if (nodes_.empty()) {
        const ShapePrimitive& s = shapes_[0];
        ShapeCrossing c[kMaxShapeCrossings];
        const int n = shape_crossings(s, to_object_space(s, o, d), c);
        bool found = false;
        for (int i = 0; i < n; ++i)
            if (t_within(c[i].t, tmin, tmax, tf) && (!found || tf < t)) {
                t = tf;
                prim = shape_prim(0, c[i].part);
                found = true;
            }
        return found;
    }
    CsgSpans spans;
    eval_csg_node(nodes_, shapes_, uint32_t(nodes_.size() - 1), o, d, spans);
    for (int i = 0; i < spans.n; ++i) {
        if (t_within(spans.s[i].t0, tmin, tmax, tf)) {
            t = tf;
            prim = spans.s[i].part0;
            return true;
        }
        if (t_within(spans.s[i].t1, tmin, tmax, tf)) {
            t = tf;
            prim = spans.s[i].part1;
            return true;
        }
    }
    return false;
}

bool AnalyticShape::any(const Vec3& o, const Vec3& d, float tmin, float tmax) const {
    float t;
    uint32_t prim;
    return closest(o, d, tmin, tmax, t, prim);
}

}  // namespace foton
