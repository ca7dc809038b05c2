#pragma once
// The scalar twin of diffuse_lobes.h: one lane's Lambertian or Oren–Nayar lobe, glossy lobe
// or both, evaluated and sampled with branches, the same IEEE operations in the same order.
#include <algorithm>
#include <cmath>

#include "glossy_scalar.h"

namespace foton::kern::scalar {

// Oren–Nayar's f / rho (bsdf.cpp's lobe_f); B = 0: Lambert's 1 / pi.
inline float oren_nayar(V3 wo, V3 wi, float a, float b) {
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

// Lane i's lobes seen from wo (local, in the shading frame).
struct DiffuseLobes {
    V3 wo, rho;
    float on_a, on_b;
    bool glossy;
    GlossyLane g;
    float wd, wg;

    DiffuseLobes(const ShadeTable& v, std::size_t i, V3 wo_local)
        : wo(wo_local),
          rho(in3(v, kDvRhoR, i)),
          on_a(v.col(kDvOnA)[i]),
          on_b(v.col(kDvOnB)[i]),
          glossy(v.col(kDvGlossKind)[i] != 0.f),
          g(v, i),
          wd(v.col(kDvDiffuseWeight)[i]),
          wg(v.col(kDvGlossWeight)[i]) {}

    // The diffuse lobe's f at wi, on wo's side (no hemisphere test).
    V3 diffuse_f(V3 wi) const {
        const float k = oren_nayar(wo, wi, on_a, on_b);
        return V3{rho.x * k, rho.y * k, rho.z * k};
    }

    // A glossy lane's two lobes: f summed, densities mixed by the sampling weights.
    float mixed(V3 wi, V3& f_sum, float& pdf_d, float& pdf_g) const {
        V3 fg;
        glossy_eval(g, wo, wi, fg, pdf_g);
        V3 fd{0.f, 0.f, 0.f};
        pdf_d = 0.f;
        if (wo.z * wi.z > 0.f) {
            fd = diffuse_f(wi);
            pdf_d = std::fabs(wi.z) * kDiffuseInvPi;
        }
        f_sum = fd + fg;
        return (wd * pdf_d + wg * pdf_g) / (wd + wg);
    }

    // Bsdf::f and Bsdf::pdf at wi.
    V3 eval(V3 wi, float& pdf) const {
        if (glossy) {
            V3 fm;
            float pdf_d, pdf_g;
            pdf = mixed(wi, fm, pdf_d, pdf_g);
            return fm;
        }
        if (!(wo.z * wi.z > 0.f)) {
            pdf = 0.f;
            return V3{0.f, 0.f, 0.f};
        }
        pdf = std::fabs(wi.z) * kDiffuseInvPi;
        return diffuse_f(wi);
    }

    // Bsdf::f at wi (eval's f).
    V3 f(V3 wi) const {
        float pdf;
        return eval(wi, pdf);
    }
};

// Bsdf::sample from lane i's (kDvUChoice, kDvU0, kDvU1): the local direction, f and pdf
// there; false where it gives none.
inline bool sample_lobes(const DiffuseLobes& b, const ShadeTable& v, std::size_t i, V3& wi, V3& f,
                         float& pdf) {
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
    if (b.wo.z < 0.f) lz = -lz;
    wi = V3{lx, ly, lz};
    if (!b.glossy) {
        // f |cos| / pdf = (rho / pi) |cos| / (|cos| / pi): the division kept as the BSDF
        // path does it.
        pdf = std::fabs(lz) * kDiffuseInvPi;
        f = b.diffuse_f(wi);
        return b.wo.z * lz > 0.f;
    }
    // The lobe by kDvUChoice in the BSDF's order, its direction, the mixture there.
    const bool glossy_first = v.col(kDvGlossFirst)[i] != 0.f;
    const float w_first = glossy_first ? b.wg : b.wd, w_second = glossy_first ? b.wd : b.wg;
    const float target = v.col(kDvUChoice)[i] * (b.wd + b.wg);
    const bool first = w_first > 0.f && (target < w_first || !(w_second > 0.f));
    const bool take_glossy = glossy_first == first;
    bool ok = true;
    if (take_glossy) ok = glossy_sample(b.g, b.wo, v.col(kDvU0)[i], v.col(kDvU1)[i], wi);
    f = V3{0.f, 0.f, 0.f};
    pdf = 0.f;
    if (!ok) return false;
    float pdf_d = 0.f, pdf_g = 0.f;
    pdf = b.mixed(wi, f, pdf_d, pdf_g);
    return (take_glossy ? pdf_g > 0.f : pdf_d > 0.f) && pdf > 0.f;
}

}  // namespace foton::kern::scalar
