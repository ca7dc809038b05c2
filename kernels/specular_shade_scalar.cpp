// The scalar twin of shade_specular: one lane at a time, the engine's branches.
#include <algorithm>
#include <cmath>

#include "fresnel.h"
#include "shade_scalar.h"
#include "specular_shade.h"

namespace foton::kern {

void shade_specular_scalar(const ShadeTable& v, std::size_t n, bool roulette) {
    using namespace scalar;
    auto col = [&](uint32_t c, std::size_t i) { return v.col(c)[i]; };
    for (std::size_t i = 0; i < n; ++i) {
        reconstruct_surface_scalar(v, i);
        const V3 p = in3(v, kDvPx, i), ng = in3(v, kDvNgx, i), ns = in3(v, kDvNsx, i);
        const V3 beta = in3(v, kDvBetaR, i), color = in3(v, kDvSpecR, i);
        V3 s, t;
        shading_frame(ns, s, t);
        const V3 wo_world = in3(v, kDvWox, i);
        const V3 wo{dot(wo_world, s), dot(wo_world, t), dot(wo_world, ns)};
        const V3 mirror{-wo.x, -wo.y, wo.z};
        V3 wi, f;
        float pdf, eta = 1.f;
        bool ok, transmit = false;
        if (col(kDvSpecKind, i) == 1.f) {
            wi = mirror;
            const float c = std::fabs(wi.z);
            ok = c != 0.f;
            V3 fr{1.f, 1.f, 1.f};
            if (col(kDvFresnel, i) == 1.f) {
                fr = {fresnel_conductor(c, col(kDvEtaR, i), col(kDvKR, i)),
                      fresnel_conductor(c, col(kDvEtaG, i), col(kDvKG, i)),
                      fresnel_conductor(c, col(kDvEtaB, i), col(kDvKB, i))};
            } else if (col(kDvFresnel, i) == 2.f) {
                const float F = fresnel_dielectric(c, 1.f, col(kDvIor, i));
                fr = {F, F, F};
            }
            const float inv = 1.f / c;
            f = {color.x * fr.x * inv, color.y * fr.y * inv, color.z * fr.z * inv};
            pdf = 1.f;
        } else {
            const bool front = col(kDvFront, i) != 0.f;
            const float ior = col(kDvIor, i);
            const float eta_i = front ? 1.f : ior, eta_t = front ? ior : 1.f;
            const float cos_i = std::fabs(wo.z);
            ok = cos_i != 0.f;
            const float F = fresnel_dielectric(cos_i, eta_i, eta_t);
            // Refraction of -wo at the normal on wo's side (optics.h's refract).
            const V3 nrm{0.f, 0.f, wo.z > 0.f ? 1.f : -1.f};
            const V3 d = wo * -1.f;
            const float e = eta_i / eta_t;
            const float ci = -dot(d, nrm);
            const float k = 1.f - e * e * (1.f - ci * ci);
            const bool tir = k < 0.f;
            V3 tr = d * e + nrm * (e * ci - std::sqrt(k));
            tr = tr * (1.f / std::sqrt(dot(tr, tr)));
            // Bsdf::sample's choice number for its one lobe: (u w) / w.
            const float w = col(kDvLobeWeight, i);
            const float uc = std::clamp((col(kDvUChoice, i) * w) / w, 0.f, 0x1.fffffep-1f);
            if (uc < F || tir) {
                wi = mirror;
                const float k_r = F / cos_i;
                f = color * k_r;
                pdf = F;
            } else {
                wi = tr;
                const float scale = (eta_i * eta_i) / (eta_t * eta_t);
                f = in3(v, kDvTransR, i) * ((1.f - F) * scale / std::fabs(tr.z));
                pdf = 1.f - F;
                eta = eta_t / eta_i;
                transmit = true;
            }
        }
        ok = ok && pdf > 0.f;
        const V3 w_world = s * wi.x + t * wi.y + ns * wi.z;
        const float side = dot(w_world, ng);
        ok = ok && (transmit ? side < 0.f : side > 0.f);
        const float kn = std::fabs(wi.z) / pdf;
        V3 nb{beta.x * (f.x * kn), beta.y * (f.y * kn), beta.z * (f.z * kn)};
        ok = ok && (nb.x != 0.f || nb.y != 0.f || nb.z != 0.f);
        const float es = col(kDvEtaScale, i) * (eta * eta);
        if (roulette) {
            const float q = std::min(1.f, std::max({nb.x, nb.y, nb.z}) * es);
            ok = ok && col(kDvURoulette, i) < q;
            nb = nb * (1.f / q);
        }
        v.col(kDvShadowValid)[i] = 0.f;
        v.col(kDvNextValid)[i] = ok ? 1.f : 0.f;
        out3(v, kDvNox, i, offset(p, ng, v.col(kDvEps)[i], w_world));
        out3(v, kDvNdx, i, w_world);
        out3(v, kDvNbetaR, i, nb);
        v.col(kDvNpdf)[i] = pdf;
        v.col(kDvNetaScale)[i] = es;
        v.col(kDvNtransmit)[i] = transmit ? 1.f : 0.f;
    }
}

}  // namespace foton::kern
