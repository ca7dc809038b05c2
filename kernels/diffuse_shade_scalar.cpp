// The scalar twin of shade_diffuse: one lane at a time, the same steps in the same order.
#include <algorithm>
#include <cmath>
#include <limits>

#include "diffuse_shade.h"
#include "glossy_scalar.h"
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

// Oren–Nayar's f / rho (bsdf.cpp's lobe_f); B = 0: Lambert's 1 / pi.
float oren_nayar(V3 wo, V3 wi, float a, float b) {
    if (b == 0.f) return kDiffuseInvPi;
    const float ci = std::fabs(wi.z), co = std::fabs(wo.z);
    const float si = std::sqrt(std::max(0.f, 1.f - ci * ci));
    const float so = std::sqrt(std::max(0.f, 1.f - co * co));
    float cos_dphi = 0.f;
    if (si > 1e-4f && so > 1e-4f) cos_dphi = std::max(0.f, (wi.x * wo.x + wi.y * wo.y) / (si * so));
    const float sin_alpha = ci > co ? so : si;
    const float tan_beta = ci > co ? si / ci : so / co;
    return kDiffuseInvPi * (a + b * cos_dphi * sin_alpha * tan_beta);
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
        const V3 rho = in3(kDvRhoR, i), beta = in3(kDvBetaR, i);
        V3 s, t;
        shading_frame(ns, s, t);
        const V3 wo_world = in3(kDvWox, i);
        const float wo_z = dot(wo_world, ns);
        const V3 wo{dot(wo_world, s), dot(wo_world, t), wo_z};
        const float on_a = v.col(kDvOnA)[i], on_b = v.col(kDvOnB)[i];

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
        const bool glossy = v.col(kDvGlossKind)[i] != 0.f;
        const GlossyLane g(v, i);
        const float wd = v.col(kDvDiffuseWeight)[i], wg = v.col(kDvGlossWeight)[i];
        auto mixed = [&](V3 wi, V3& f_sum, float& pdf_d, float& pdf_g) {
            V3 fg;
            glossy_eval(g, wo, wi, fg, pdf_g);
            V3 fd{0.f, 0.f, 0.f};
            pdf_d = 0.f;
            if (wo_z * wi.z > 0.f) {
                const float fk = oren_nayar(wo, wi, on_a, on_b);
                fd = V3{rho.x * fk, rho.y * fk, rho.z * fk};
                pdf_d = std::fabs(wi.z) * kDiffuseInvPi;
            }
            f_sum = fd + fg;
            return (wd * pdf_d + wg * pdf_g) / (wd + wg);
        };

        // Next event estimation.
        const float cos_l = dot(lw, ns);
        bool shadow = pl > 0.f && dot(lw, ng) > 0.f && (glossy || wo_z * cos_l > 0.f);
        V3 value{0.f, 0.f, 0.f};
        if (shadow && glossy) {
            V3 fm;
            float pdf_d, pdf_g;
            const float pm = mixed(V3{dot(lw, s), dot(lw, t), cos_l}, fm, pdf_d, pdf_g);
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
            const float fk = oren_nayar(wo, V3{dot(lw, s), dot(lw, t), cos_l}, on_a, on_b);
            value = {beta.x * (rho.x * fk) * li.x * k, beta.y * (rho.y * fk) * li.y * k,
                     beta.z * (rho.z * fk) * li.z * k};
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

        // The continuation: a cosine-weighted direction.
        const float da = 2.f * v.col(kDvU0)[i] - 1.f, db = 2.f * v.col(kDvU1)[i] - 1.f;
        float lx = 0.f, ly = 0.f;
        if (da != 0.f || db != 0.f) {
            float sx, cx;
            if (std::fabs(da) > std::fabs(db)) {
                sincos_quarter(0.25f * kDiffusePi * (db / da), sx, cx);
                lx = da * cx;
                ly = da * sx;
            } else {
                // The angle pi/2 - x: cosine and sine swap.
                sincos_quarter(0.25f * kDiffusePi * (da / db), sx, cx);
                lx = db * sx;
                ly = db * cx;
            }
        }
        float lz = std::sqrt(std::max(0.f, 1.f - lx * lx - ly * ly));
        if (wo_z < 0.f) lz = -lz;
        bool next;
        V3 wi, nb;
        float pdf;
        if (glossy) {
            // Bsdf::sample: the lobe by kDvUChoice in the BSDF's order, its direction, then
            // the mixture's f and pdf there.
            const bool glossy_first = v.col(kDvGlossFirst)[i] != 0.f;
            const float w_first = glossy_first ? wg : wd, w_second = glossy_first ? wd : wg;
            const float target = v.col(kDvUChoice)[i] * (wd + wg);
            const bool first = w_first > 0.f && (target < w_first || !(w_second > 0.f));
            const bool take_glossy = glossy_first == first;
            V3 wl{lx, ly, lz};
            next = true;
            if (take_glossy) next = glossy_sample(g, wo, v.col(kDvU0)[i], v.col(kDvU1)[i], wl);
            V3 fm{0.f, 0.f, 0.f};
            float pdf_d = 0.f, pdf_g = 0.f;
            pdf = 0.f;
            if (next) {
                pdf = mixed(wl, fm, pdf_d, pdf_g);
                next = (take_glossy ? pdf_g > 0.f : pdf_d > 0.f) && pdf > 0.f;
            }
            wi = s * wl.x + t * wl.y + ns * wl.z;
            const float k = std::fabs(wl.z) / pdf;
            nb = V3{beta.x * (fm.x * k), beta.y * (fm.y * k), beta.z * (fm.z * k)};
            next = next && dot(wi, ng) > 0.f;
        } else {
            const float cz = std::fabs(lz);
            next = wo_z * lz > 0.f;
            wi = s * lx + t * ly + ns * lz;
            next = next && dot(wi, ng) > 0.f;
            // f |cos| / pdf = (rho / pi) |cos| / (|cos| / pi): the division kept as the BSDF
            // path does it.
            pdf = cz * kDiffuseInvPi;
            const float k = cz / pdf;
            const float fk = oren_nayar(wo, V3{lx, ly, lz}, on_a, on_b);
            nb = V3{beta.x * ((rho.x * fk) * k), beta.y * ((rho.y * fk) * k),
                    beta.z * ((rho.z * fk) * k)};
        }
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
