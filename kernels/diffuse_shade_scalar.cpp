// The scalar twin of shade_diffuse: one lane at a time, the same steps in the same order.
#include <algorithm>
#include <cmath>
#include <limits>

#include "diffuse_lobes_scalar.h"
#include "diffuse_shade.h"
#include "shade_scalar.h"

namespace foton::kern {

namespace {

using namespace scalar;

float mis_weight(const DiffuseRules& r, float pa, float pb) {
    switch (r.mis) {
        case DiffuseMis::Balance:
            return pa / (pa + pb);
        case DiffuseMis::Power:  // exponent 2 (the caller keeps others scalar)
            return pa * pa / (pa * pa + pb * pb);
        case DiffuseMis::Maximum:
            return pa * kDiffuseMaxTie >= pb ? 1.f : 0.f;
        case DiffuseMis::Mean:
            return pb > 0.f ? 0.5f : 1.f;
        case DiffuseMis::None:
            break;
    }
    return 1.f;
}

}  // namespace

void shade_diffuse_scalar(const ShadeTable& v, std::size_t n, const DiffuseRules& rules) {
    auto in3 = [&](uint32_t c, std::size_t i) {
        return V3{v.col(c)[i], v.col(c + 1)[i], v.col(c + 2)[i]};
    };
    auto out3 = [&](uint32_t c, std::size_t i, V3 a) {
        v.col(c)[i] = a.x;
        v.col(c + 1)[i] = a.y;
        v.col(c + 2)[i] = a.z;
    };
    for (std::size_t i = 0; i < n; ++i) {
        reconstruct_surface_scalar(v, i);
        const V3 p = in3(kDvPx, i), ng = in3(kDvNgx, i), ns = in3(kDvNsx, i);
        const float eps = v.col(kDvEps)[i];
        const V3 beta = in3(kDvBetaR, i);
        V3 s, t;
        shading_frame(ns, s, t);
        const V3 wo_world = in3(kDvWox, i);
        const float wo_z = dot(wo_world, ns);
        const DiffuseLobes lobes(v, i, V3{dot(wo_world, s), dot(wo_world, t), wo_z});

        // A rectangle's or a triangle's sample: a point uniform on its area, its solid-angle
        // density.
        float pl = v.col(kDvLightPdf)[i], dist = v.col(kDvLdist)[i];
        V3 lw = in3(kDvLwx, i), q = in3(kDvLpx, i), nq = in3(kDvLnx, i);
        const float kind = v.col(kDvLkind)[i];
        if (kind == kLightParallelogram || kind == kLightTriangle) {
            const float a = v.col(kDvLu0)[i], b = v.col(kDvLu1)[i];
            const V3 c1 = in3(kDvLe1x, i), c2 = in3(kDvLe2x, i);
            if (kind == kLightTriangle) {
                // warp::uniform_triangle, then the corners weighted as sample_li weighs them.
                float b0, b1;
                if (a < b) {
                    b0 = 0.5f * a;
                    b1 = b - b0;
                } else {
                    b1 = 0.5f * b;
                    b0 = a - b1;
                }
                const float bx = b1, by = (1.f - b0) - b1;
                q = (q * ((1.f - bx) - by) + c1 * bx) + c2 * by;
            } else {
                q = (q + c1 * a) + c2 * b;
            }
            const V3 to = q - p;
            const float d2 = dot(to, to);
            dist = std::sqrt(d2);
            lw = to * (1.f / dist);
            float cos_r = -dot(nq, lw);
            if (v.col(kDvLtwoSided)[i] != 0.f) cos_r = std::fabs(cos_r);
            pl = d2 != 0.f && cos_r > 0.f ? pl * (d2 / (cos_r * v.col(kDvLarea)[i])) : 0.f;
            if (dot(nq, lw) >= 0.f) nq = nq * -1.f;
        }

        // An emitting sphere's sample: uniform in the cone it subtends (none from inside).
        if (kind == kLightSphere) {
            const V3 c = in3(kDvLpx, i);
            const float r = v.col(kDvLe1x)[i];
            const V3 to_c = c - p;
            const float dc2 = dot(to_c, to_c);
            const float r2 = r * r;
            const bool outside = dc2 > r2 * 1.0001f;
            const V3 wc = to_c * (1.f / std::sqrt(dc2));
            const float sin2_max = r2 / dc2;
            const float omc = sin2_max / (1.f + std::sqrt(std::max(0.f, 1.f - sin2_max)));
            const float vv = v.col(kDvLu0)[i] * omc;
            const float cos_t = 1.f - vv, sin2_t = vv * (2.f - vv);
            const float cos_a = sin2_t / std::sqrt(sin2_max) +
                                cos_t * std::sqrt(std::max(0.f, 1.f - sin2_t / sin2_max));
            const float sin_a = std::sqrt(std::max(0.f, 1.f - cos_a * cos_a));
            float sin_p, cos_p;
            sincos_turn(v.col(kDvLu1)[i], sin_p, cos_p);
            V3 fs, ft;
            shading_frame(wc, fs, ft);
            const float lx = sin_a * cos_p, ly = sin_a * sin_p, lz = -cos_a;
            const V3 n{(fs.x * lx + ft.x * ly) + wc.x * lz, (fs.y * lx + ft.y * ly) + wc.y * lz,
                       (fs.z * lx + ft.z * ly) + wc.z * lz};
            q = c + n * r;
            const V3 to = q - p;
            dist = std::sqrt(dot(to, to));
            const float pdf = 1.f / ((2.f * kDiffusePi) * omc);
            pl = outside && pdf > 0.f && dist > 0.f ? pl * pdf : 0.f;
            lw = to * (1.f / dist);
            nq = n;
        }

        // A glossy lobe beside the diffuse one: f is the two lobes' sum, the pdf their
        // densities mixed by the sampling weights (Bsdf::f, Bsdf::pdf).
        const bool glossy = lobes.glossy;
        // Next event estimation.
        const float cos_l = dot(lw, ns);
        bool shadow = pl > 0.f && dot(lw, ng) > 0.f && (glossy || wo_z * cos_l > 0.f);
        V3 value{0.f, 0.f, 0.f};
        if (shadow && glossy) {
            V3 fm;
            float pdf_d, pdf_g;
            const float pm = lobes.mixed(V3{dot(lw, s), dot(lw, t), cos_l}, fm, pdf_d, pdf_g);
            const float w = v.col(kDvLightFull)[i] != 0.f ? 1.f : mis_weight(rules, pl, pm);
            const float k = std::fabs(cos_l) * w / pl;
            const V3 li = in3(kDvLiR, i);
            value = {beta.x * fm.x * li.x * k, beta.y * fm.y * li.y * k, beta.z * fm.z * li.z * k};
            shadow = value.x != 0.f || value.y != 0.f || value.z != 0.f;
        } else if (shadow) {
            const float pb = std::fabs(cos_l) * kDiffuseInvPi;
            const float w = v.col(kDvLightFull)[i] != 0.f ? 1.f : mis_weight(rules, pl, pb);
            const float k = std::fabs(cos_l) * w / pl;
            const V3 li = in3(kDvLiR, i);
            const V3 fl = lobes.diffuse_f(V3{dot(lw, s), dot(lw, t), cos_l});
            value = {beta.x * fl.x * li.x * k, beta.y * fl.y * li.y * k, beta.z * fl.z * li.z * k};
            shadow = value.x != 0.f || value.y != 0.f || value.z != 0.f;
        }
        v.col(kDvShadowValid)[i] = shadow ? 1.f : 0.f;
        out3(kDvSvR, i, value);
        if (std::isinf(dist)) {
            out3(kDvSox, i, offset(p, ng, eps, lw));
            out3(kDvSdx, i, lw);
            v.col(kDvStmax)[i] = std::numeric_limits<float>::infinity();
        } else {
            // Both ends pushed off their surfaces towards each other (surface.h).
            const V3 o = offset(p, ng, eps, q - p);
            const float eps_q = kDiffuseOffset *
                                (std::max({std::fabs(q.x), std::fabs(q.y), std::fabs(q.z)}) + dist);
            const V3 end = q + (dot(nq, o - q) >= 0.f ? nq : nq * -1.f) * eps_q;
            const V3 d = end - o;
            const float len = std::sqrt(dot(d, d));
            out3(kDvSox, i, o);
            out3(kDvSdx, i, len > 0.f ? d * (1.f / len) : d);
            v.col(kDvStmax)[i] = len * (1.f - 1e-4f);
        }

        // The continuation (Bsdf::sample), throughput f |cos| / pdf.
        V3 wl, f;
        float pdf;
        bool next = sample_lobes(lobes, v, i, wl, f, pdf);
        const V3 wi = s * wl.x + t * wl.y + ns * wl.z;
        const float k = std::fabs(wl.z) / pdf;
        V3 nb{beta.x * (f.x * k), beta.y * (f.y * k), beta.z * (f.z * k)};
        next = next && dot(wi, ng) > 0.f;
        next = next && (nb.x != 0.f || nb.y != 0.f || nb.z != 0.f);
        if (rules.roulette) {
            const float q = std::min(1.f, std::max({nb.x, nb.y, nb.z}) * v.col(kDvEtaScale)[i]);
            next = next && v.col(kDvURoulette)[i] < q;
            nb = nb * (1.f / q);
        }
        v.col(kDvNextValid)[i] = next ? 1.f : 0.f;
        out3(kDvNox, i, offset(p, ng, eps, wi));
        out3(kDvNdx, i, wi);
        out3(kDvNbetaR, i, nb);
        v.col(kDvNpdf)[i] = pdf;
    }
}

}  // namespace foton::kern
