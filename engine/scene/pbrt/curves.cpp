// Shape "curve": pbrt-v4's cubic (or quadratic) Bézier and B-spline curves of type flat,
// cylinder or ribbon, placed in world space. The curves of one material, type and medium form
// one object (a hair model's thousands of statements become one curve set).
#include <cmath>
#include <stdexcept>

#include "importer.h"

namespace foton::pbrt {

void Importer::curve(const Token& t, const ParamList& p) {
    const std::string what = "Shape \"curve\"";
    if (gs_.area.id >= 0) fail(t, what + ": curves cannot be area lights");
    if (shape_alpha_ < 1.f || shape_alpha_texture_ >= 0)
        fail(t, what + ": alpha on curves is not supported");
    const std::string type = p.text("type", "flat");
    CurveForm form;
    if (type == "flat") {
        form = CurveForm::Flat;
    } else if (type == "cylinder") {
        form = CurveForm::Cylinder;
    } else if (type == "ribbon") {
        form = CurveForm::Ribbon;
    } else {
        fail(t, what + ": type '" + type + "' (flat, cylinder or ribbon)");
    }
    CurveInput in;
    in.points = p.triples("P");
    in.basis = p.text("basis", "bezier");
    in.degree = p.integer("degree", 3);
    const float width = p.real("width", 1.f);
    in.width0 = p.real("width0", width);
    in.width1 = p.real("width1", width);
    std::vector<Vec3> normals = p.triples("N");
    if (form == CurveForm::Ribbon && normals.empty())
        fail(t, what + ": a ribbon needs \"normal N\" (one per segment end)");
    if (form != CurveForm::Ribbon && !normals.empty()) {
        warn(file(), t.line, what + ": N ignored (only ribbons have normals)");
        normals.clear();
    }
    // pbrt splits curves for its BVH; foton's curve BVH holds every segment already.
    p.integer("splitdepth", 3);
    // The curve is intersected in world space: points and normals placed by the CTM, widths
    // scaled by its mean scale (exact for uniform scales, which is what curve files use).
    for (Vec3& q : in.points) q = gs_.ctm.point(q);
    for (const Vec3& n : normals) in.normals.push_back(gs_.ctm.normal(n));
    const float scale = std::cbrt(std::fabs(gs_.ctm.determinant()));
    const float sx = length(gs_.ctm.vector({1.f, 0.f, 0.f})),
                sy = length(gs_.ctm.vector({0.f, 1.f, 0.f})),
                sz = length(gs_.ctm.vector({0.f, 0.f, 1.f}));
    if (std::max({sx, sy, sz}) > 1.001f * std::min({sx, sy, sz}))
        warn(file(), t.line, what + ": a non-uniform scale; widths scaled by its mean");
    in.width0 *= scale;
    in.width1 *= scale;
    const MediumInterface media = shape_media();
    if (media.transition()) fail(t, what + ": a curve cannot bound a medium (MediumInterface)");
    const uint32_t material = scene_material(gs_);
    // Inside ObjectBegin the curves belong to the object, placed again by each instance.
    Scene& into = target();
    const auto key = std::make_tuple(&into, material, int(form), media.inside);
    auto it = curve_objects_.find(key);
    if (it == curve_objects_.end()) {
        CurveSet set;
        set.form = form;
        const uint32_t id = into.add_curves(std::move(set), material);
        into.objects[id].media = media;
        it = curve_objects_.emplace(key, id).first;
    }
    try {
        append_curve(into.curves[into.objects[it->second].index], in);
    } catch (const std::invalid_argument& e) {
        fail(t, what + ": " + e.what());
    }
    warn_unused(p, what);
    count("Shape curve (" + type + ")");
}

}  // namespace foton::pbrt
