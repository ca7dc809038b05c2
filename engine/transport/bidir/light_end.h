#pragma once
// The light end of a connection: light vertex j's BSDF (rebuilt from its material) or, for a
// medium vertex, its phase function, evaluated towards the camera vertex that joins it.
#include <cmath>
#include <optional>

#include "engine/core/warp.h"
#include "engine/scene/medium.h"
#include "engine/scene/scene.h"
#include "light_vertices.h"
#include "vcm_joins.h"

namespace foton {

// A surface light vertex's BSDF in its shading frame.
struct LightVertexBsdf {
    std::optional<Material> scratch;
    const Material& m;
    warp::Frame frame;
    Vec3 wo;
    LightVertexBsdf(const Scene& scene, const LightVertices& v, std::size_t i)
        : m(scene.material_at(v.geom[i], v.uv[i], scratch)), frame(v.ns[i], v.ss[i]) {
        wo = frame.to_local(v.wo[i]);
    }
};

// What light vertex j gives a connection arriving along dir (from the camera vertex to it):
// the value with the densities (e), its continuation probability (q) and |cos| at it (cos_l,
// 1 in a medium); false where it sends nothing back that way.
inline bool light_end(const Scene& scene, const LightVertices& lv, uint32_t j, const Vec3& dir,
                      LobeEval& e, float& q, float& cos_l) {
    if (lv.in_medium(j)) {
        const float phase =
            henyey_greenstein(dot(lv.wo[j], -dir), scene.media[std::size_t(lv.medium[j])].g);
        e = {RGB{phase}, phase, phase};
        q = 1.f;
        cos_l = 1.f;
        return true;
    }
    cos_l = std::fabs(dot(dir, lv.ng[j]));
    if (cos_l == 0.f) return false;
    const LightVertexBsdf lb(scene, lv, j);
    // On the side the vertex was reached from, or behind it through a rough dielectric.
    if (!(dot(dir, lv.ng[j]) < 0.f) && !lb.m.bsdf.transmits_non_delta()) return false;
    const Vec3 dl = lb.frame.to_local(-dir);
    const BsdfContext lctx{lv.front[j] != 0, Transport::Importance};
    const BsdfContext lrctx{lv.front[j] != 0, Transport::Radiance};
    const RGB fl = lb.m.bsdf.f(lb.wo, dl, lctx);
    if (fl.is_black()) return false;
    e = {fl, lb.m.bsdf.pdf(lb.wo, dl, lctx), lb.m.bsdf.pdf(dl, lb.wo, lrctx)};
    q = lb.m.bsdf.continuation();
    return true;
}

}  // namespace foton
