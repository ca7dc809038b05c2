// The scalar twin of shade_importance: one lane at a time, the same steps in the same order.
#include <algorithm>
#include <cmath>

#include "diffuse_lobes_scalar.h"
#include "importance_shade.h"

namespace foton::kern {

using namespace scalar;

void shade_importance_scalar(const ShadeTable& v, std::size_t n, bool roulette) {
    for (std::size_t i = 0; i < n; ++i) {
        reconstruct_surface_scalar(v, i);
        const V3 p = in3(v, kDvPx, i), ng = in3(v, kDvNgx, i), ns = in3(v, kDvNsx, i);
        const float eps = v.col(kDvEps)[i];
        const V3 beta = in3(v, kDvBetaR, i);
        V3 s, t;
        shading_frame(ns, s, t);
        const V3 wo_world = in3(v, kDvWox, i);
        const float wo_z = dot(wo_world, ns);
        const DiffuseLobes lobes(v, i, V3{dot(wo_world, s), dot(wo_world, t), wo_z});
        const float wo_ng = std::fabs(dot(wo_world, ng));
        const bool live = wo_ng != 0.f;
        const float adj = std::fabs(wo_z) / wo_ng;

        // The connection to the eye.
        const V3 eye = in3(v, kDvLpx, i);
        const V3 to = eye - p;
        const V3 wc = to * (1.f / std::sqrt(dot(to, to)));
        const float c_ng = dot(wc, ng);
        V3 value{0.f, 0.f, 0.f};
        bool connect = false;
        if (live && c_ng > 0.f) {
            const V3 fc = lobes.f(V3{dot(wc, s), dot(wc, t), dot(wc, ns)});
            const float kc = adj * c_ng;
            value = V3{beta.x * fc.x * kc, beta.y * fc.y * kc, beta.z * fc.z * kc};
            connect = value.x != 0.f || value.y != 0.f || value.z != 0.f;
            if (!connect) value = V3{0.f, 0.f, 0.f};
        }
        const V3 o = offset(p, ng, eps, wc);
        const V3 oe = eye - o;
        v.col(kDvShadowValid)[i] = connect ? 1.f : 0.f;
        out3(v, kDvSvR, i, value);
        out3(v, kDvSox, i, o);
        out3(v, kDvSdx, i, wc);
        v.col(kDvStmax)[i] = std::sqrt(dot(oe, oe)) * (1.f - 1e-4f);

        // The continuation.
        V3 wl, f;
        float pdf;
        bool next = sample_lobes(lobes, v, i, wl, f, pdf) && live;
        const V3 wi = s * wl.x + t * wl.y + ns * wl.z;
        const float side = dot(wi, ng);
        const float k = adj * std::fabs(side) / pdf;
        V3 nb{beta.x * (f.x * k), beta.y * (f.y * k), beta.z * (f.z * k)};
        next = next && side > 0.f && (nb.x != 0.f || nb.y != 0.f || nb.z != 0.f);
        if (roulette) {
            const float q = std::min(1.f, std::max({nb.x, nb.y, nb.z}));
            next = next && v.col(kDvURoulette)[i] < q;
            nb = nb * (1.f / q);
        }
        v.col(kDvNextValid)[i] = next ? 1.f : 0.f;
        out3(v, kDvNox, i, offset(p, ng, eps, wi));
        out3(v, kDvNdx, i, wi);
        out3(v, kDvNbetaR, i, nb);
        v.col(kDvNpdf)[i] = pdf;
    }
}

}  // namespace foton::kern
