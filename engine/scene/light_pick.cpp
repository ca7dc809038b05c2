// Next event estimation's choice of a light: by power, uniformly, or through the light BVH
// (light_bvh.h), and the probabilities MIS weighs a light that a BSDF sample hit by.
#include <algorithm>
#include <cmath>
#include <string>

#include "engine/core/error.h"

#include "light_set.h"

namespace foton {

namespace {

// What a light sends towards points around it, for the light BVH. Area lights emit up to
// 90 degrees past their normals; points and spheres everywhere; a spot inside its cone.
// Power as pbrt-v4 weighs it: radiance * area * pi for area lights, intensity * 4 pi for
// points and spots (only ratios at a node matter, and every weight reaches every light that
// can light the point, so any choice stays unbiased).
LightBounds bounds_of(const Emitter& e) {
    LightBounds b;
    const float lum = std::max(0.f, e.value.luminance());
    switch (e.type) {
        case EmitterType::Point:
            b.box.extend(e.p);
            b.cos_o = -1.f;
            b.phi = lum * 4.f * kPi;
            break;
        case EmitterType::Spot:
            b.box.extend(e.p);
            b.axis = e.n;
            b.cos_o = e.cos_outer;
            // Light leaves along the cone's directions only: 0 degrees past them.
            b.cos_e = 1.f;
            b.phi = lum * 4.f * kPi;
            break;
        case EmitterType::Rect:
            b.box.extend(e.p);
            b.box.extend(e.p + e.e1);
            b.box.extend(e.p + e.e2);
            b.box.extend(e.p + e.e1 + e.e2);
            b.axis = e.n;
            b.two_sided = e.two_sided;
            b.phi = lum * e.area * kPi * (e.two_sided ? 2.f : 1.f);
            break;
        case EmitterType::Sphere:
            b.box.extend(e.p - Vec3{e.radius, e.radius, e.radius});
            b.box.extend(e.p + Vec3{e.radius, e.radius, e.radius});
            b.cos_o = -1.f;
            b.phi = lum * e.area * kPi * (e.two_sided ? 2.f : 1.f);
            break;
        default:
            break;
    }
    return b;
}

}  // namespace

void LightSet::build_bvh() {
    std::vector<LightBounds> bounds;
    first_prim_.assign(emitters_.size(), kWholeEmitter);
    for (uint32_t i = 0; i < emitters_.size(); ++i) {
        const Emitter& e = emitters_[i];
        if (e.is_infinite()) {
            infinite_.push_back(i);
            continue;
        }
        first_prim_[i] = uint32_t(bounds.size());
        if (e.type != EmitterType::Mesh) {
            bounds.push_back(bounds_of(e));
            prim_emitter_.push_back(i);
            prim_tri_.push_back(kWholeEmitter);
            continue;
        }
        // Every triangle its own light, facing where sample_li's normal faces.
        const float lum = std::max(0.f, e.value.luminance());
        for (uint32_t t = 0; t < e.tri_cdf.size(); ++t) {
            Vec3 p0, p1, p2;
            scene_->world_corners(e.geom, t, p0, p1, p2);
            const Vec3 c = cross(p1 - p0, p2 - p0);
            const float area = 0.5f * length(c);
            LightBounds b;
            b.box.extend(p0);
            b.box.extend(p1);
            b.box.extend(p2);
            if (area > 0.f) b.axis = c / (2.f * area);
            b.two_sided = e.two_sided;
            b.phi = lum * area * kPi * (e.two_sided ? 2.f : 1.f);
            bounds.push_back(b);
            prim_emitter_.push_back(i);
            prim_tri_.push_back(t);
        }
    }
    // The descent kernel indexes nodes by floats (kernels/light_tree.h): 2^23 lights make
    // 2^24 - 1 nodes.
    if (bounds.size() >= kern::LightTree::kMaxNodes / 2)
        throw InputError(scene_->source, 0,
                         "light_selection=\"bvh\" takes at most " +
                             std::to_string(kern::LightTree::kMaxNodes / 2 - 1) +
                             " lights (each emitting triangle one); this scene has " +
                             std::to_string(bounds.size()));
    bvh_.build(bounds);
    const float trees = bvh_.empty() ? 0.f : 1.f;
    p_infinite_ =
        infinite_.empty() ? 0.f : float(infinite_.size()) / (float(infinite_.size()) + trees);
}

bool LightSet::pick(float u, const Vec3& p, const Vec3& n, LightPick& out) const {
    out.tri = kWholeEmitter;
    switch (selection_) {
        case LightSelection::Power:
            out.light = select(u, out.pmf);
            return true;
        case LightSelection::Uniform: {
            const std::size_t count = emitters_.size();
            out.light = uint32_t(std::min(count - 1, std::size_t(u * float(count))));
            out.pmf = 1.f / float(count);
            return true;
        }
        case LightSelection::Bvh:
            break;
    }
    if (pick_infinite(u, out)) return true;
    uint32_t prim;
    float pmf;
    if (!bvh_.sample(u, p, n, prim, pmf)) return false;
    out = tree_pick(prim, pmf);
    return true;
}

bool LightSet::pick_infinite(float& u, LightPick& out) const {
    if (u < p_infinite_) {
        const std::size_t count = infinite_.size();
        out.light = infinite_[std::min(count - 1, std::size_t(u / p_infinite_ * float(count)))];
        out.tri = kWholeEmitter;
        out.pmf = p_infinite_ / float(count);
        return true;
    }
    u = std::min((u - p_infinite_) / (1.f - p_infinite_), 0x1.fffffep-1f);
    return false;
}

LightPick LightSet::tree_pick(uint32_t prim, float pmf) const {
    return {prim_emitter_[prim], prim_tri_[prim], pmf * (1.f - p_infinite_)};
}

void LightPickLanes::resize(std::size_t n) {
    const std::size_t padded = (n + 15) / 16 * 16;
    for (std::vector<float>* v : {&u, &px, &py, &pz, &nx, &ny, &nz, &pmf}) v->assign(padded, 0.f);
    light.assign(padded, 0);
    out.assign(padded, LightPick{});
}

void LightSet::pick_lanes(LightPickLanes& lanes, std::size_t count) const {
    if (selection_ != LightSelection::Bvh) {
        for (std::size_t i = 0; i < count; ++i) {
            LightPick& pick = lanes.out[i];
            if (!this->pick(lanes.u[i], Vec3{}, Vec3{}, pick)) pick.pmf = 0.f;
        }
        return;
    }
    // Lights at infinity here, the tree's share through the descent kernel with u rescaled
    // as pick() rescales it.
    for (std::size_t i = 0; i < count; ++i)
        if (pick_infinite(lanes.u[i], lanes.out[i]))
            lanes.u[i] = -1.f;  // taken: the kernel's pick for it is not read
    if (bvh_.empty()) return;
    const kern::LightQueries q{lanes.px.data(), lanes.py.data(),    lanes.pz.data(),
                               lanes.nx.data(), lanes.ny.data(),    lanes.nz.data(),
                               lanes.u.data(),  lanes.light.data(), lanes.pmf.data()};
    kern::pick_lights(bvh_.tree(), q, count);
    for (std::size_t i = 0; i < count; ++i)
        if (lanes.u[i] >= 0.f) lanes.out[i] = tree_pick(lanes.light[i], lanes.pmf[i]);
}

float LightSet::pick_pmf(uint32_t light, uint32_t tri, const Vec3& p, const Vec3& n) const {
    switch (selection_) {
        case LightSelection::Power:
            return pmf_[light];
        case LightSelection::Uniform:
            return 1.f / float(emitters_.size());
        case LightSelection::Bvh:
            break;
    }
    if (emitters_[light].is_infinite()) return p_infinite_ / float(infinite_.size());
    const uint32_t first = first_prim_[light];
    if (first == kWholeEmitter) return 0.f;
    const uint32_t prim = emitters_[light].type == EmitterType::Mesh ? first + tri : first;
    return bvh_.pmf(prim, p, n) * (1.f - p_infinite_);
}

float LightSet::nee_pdf(uint32_t light, uint32_t tri, const Vec3& p, const Vec3& n, const Vec3& q,
                        const Vec3& nq) const {
    // Under power and uniform selection a mesh is one light, its triangles chosen by area.
    const uint32_t unit = selection_ == LightSelection::Bvh ? tri : kWholeEmitter;
    const float pmf = pick_pmf(light, unit, p, n);
    return pmf == 0.f ? 0.f : pmf * pdf_li(light, p, q, nq, unit);
}

float LightSet::nee_environment_pdf(const Vec3& p, const Vec3& wi) const {
    if (environment_ < 0) return 0.f;
    return pick_pmf(uint32_t(environment_), kWholeEmitter, Vec3{}, Vec3{}) *
           scene_->environment->pdf(p, wi);
}

}  // namespace foton
