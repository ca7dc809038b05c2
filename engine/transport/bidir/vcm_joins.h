#pragma once
// What a camera vertex gets from joining a light vertex j, given both BSDFs' values and
// densities at the joining directions (from the engine's Bsdf one at a time, or from the
// lobe-pair kernel in batches: camera_subpaths.cpp): a connection's contribution and a
// merge's term, with their MIS weights (vcm_mis.h).
#include <cmath>

#include "engine/core/rgb.h"
#include "light_vertices.h"
#include "vcm_mis.h"

namespace foton {

// A BSDF at a pair of directions: f(wo, wi), pdf(wo -> wi), pdf(wi -> wo).
struct LobeEval {
    RGB f;
    float pdf = 0.f, pdf_rev = 0.f;
};

// Connection (s = length[j] + 1, t) of camera vertex (throughput beta, sums m, continuation
// probability q) to light vertex j (continuation probability ql) at squared distance dist2,
// with the cosines at the camera vertex (geometric cos_c, shading |dc.z|) and at the light
// vertex (cos_l); 1 for a medium vertex, where no merge can be either (cam_medium: the
// camera vertex is one).
inline RGB connection_value(const VcmWeights& W, const SubpathMis& m, const RGB& beta, int t,
                            const LightVertices& lv, uint32_t j, const LobeEval& cam, float q,
                            const LobeEval& light, float ql, float dist2, float cos_c, float cos_l,
                            float cos_shading, bool cam_medium = false) {
    const float cam_pdf_a = cam.pdf * q * cos_l / dist2;
    const float light_pdf_a = light.pdf * ql * cos_c / dist2;
    const float w_light = W.mis(cam_pdf_a) * (W.merge_at(lv.in_medium(j)) + lv.dvcm[j] +
                                              lv.dvc[j] * W.mis(light.pdf_rev * ql));
    const float w_camera =
        W.mis(light_pdf_a) * (W.merge_at(cam_medium) + m.dvcm + m.dvc * W.mis(cam.pdf_rev * q));
    const float w = W.strategy(int(lv.length[j]) + 1, t, 1.f / (w_light + 1.f + w_camera));
    return beta * cam.f * lv.beta[j] * light.f * (cos_shading * lv.adj[j] * cos_l * w / dist2);
}

// A merge's term f lv.beta w (the caller scales the sum by beta and the kernel's norm).
inline RGB merge_term(const VcmWeights& W, const SubpathMis& m, const LightVertices& lv, uint32_t j,
                      const LobeEval& cam, float q) {
    const float w_light = lv.dvcm[j] * W.vc_weight + lv.dvm[j] * W.mis(cam.pdf * q);
    const float w_camera = m.dvcm * W.vc_weight + m.dvm * W.mis(cam.pdf_rev * q);
    return cam.f * lv.beta[j] * (1.f / (w_light + 1.f + w_camera));
}

}  // namespace foton
