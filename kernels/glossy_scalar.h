#pragma once
// The scalar twin of glossy_lanes.h: one lane's glossy lobe (modified Phong, Beckmann or
// cos^e microfacets), its f and pdf and a sampled direction, with branches, the same IEEE
// operations in the same order.
#include <limits>

#include "fresnel.h"
#include "glossy_math.h"
#include "shade_scalar.h"

namespace foton::kern::scalar {

struct GlossyLane {
    float kind, nu, nv;
    V3 color;
    float fresnel, ior;
    V3 eta, k;

    GlossyLane(const ShadeTable& v, std::size_t i)
        : kind(v.col(kDvGlossKind)[i]),
          nu(v.col(kDvGlossNu)[i]),
          nv(v.col(kDvGlossNv)[i]),
          color(in3(v, kDvGlossR, i)),
          fresnel(v.col(kDvFresnel)[i]),
          ior(v.col(kDvIor)[i]),
          eta(in3(v, kDvEtaR, i)),
          k(in3(v, kDvKR, i)) {}
    bool microfacet() const {
        return kind == kGlossBeckmann || kind == kGlossCosPower || kind == kGlossGgx;
    }
};

inline V3 glossy_fresnel(const GlossyLane& g, float c) {
    if (g.fresnel == 2.f) {
        const float fd = fresnel_dielectric(c, 1.f, g.ior);
        return V3{fd, fd, fd};
    }
    if (g.fresnel == 1.f)
        return V3{fresnel_conductor(c, g.eta.x, g.k.x), fresnel_conductor(c, g.eta.y, g.k.y),
                  fresnel_conductor(c, g.eta.z, g.k.z)};
    return V3{1.f, 1.f, 1.f};
}

inline float glossy_d(const GlossyLane& g, V3 h) {
    const float c = h.z;
    if (!(c > 0.f)) return 0.f;
    if (g.kind == kGlossBeckmann) {
        const float c2 = c * c;
        const float tan2 = (1.f - c2) / c2;
        const float a = g.nu;
        return exp_poly(-tan2 / (a * a)) / ((((kDiffusePi * a) * a) * c2) * c2);
    }
    if (g.kind == kGlossGgx) {
        const float x = h.x / g.nu, y = h.y / g.nv;
        const float s = c * c + x * x + y * y;
        return 1.f / ((((kDiffusePi * g.nu) * g.nv) * s) * s);
    }
    const float s2 = h.x * h.x + h.y * h.y;
    const float e = s2 > 0.f ? (g.nu * h.x * h.x + g.nv * h.y * h.y) / s2 : g.nu;
    return std::sqrt((g.nu + 2.f) * (g.nv + 2.f)) * (0.5f * kDiffuseInvPi) * pow_poly(c, e);
}

inline float ggx_lambda(const GlossyLane& g, V3 w) {
    const float z2 = w.z * w.z;
    if (z2 == 0.f) return std::numeric_limits<float>::infinity();
    const float ax = w.x * g.nu, ay = w.y * g.nv;
    const float a2t2 = (ax * ax + ay * ay) / z2;
    return 0.5f * (std::sqrt(1.f + a2t2) - 1.f);
}

inline V3 ggx_visible_normal(const GlossyLane& g, V3 wo, float u0, float sin_p, float cos_p) {
    const V3 ws{g.nu * wo.x, g.nv * wo.y, wo.z};
    const V3 wh = ws * (1.f / std::sqrt(dot(ws, ws)));
    const float l2 = wh.x * wh.x + wh.y * wh.y;
    const float il = 1.f / std::sqrt(l2);
    const V3 t1 = l2 > 0.f ? V3{-wh.y * il, wh.x * il, 0.f} : V3{1.f, 0.f, 0.f};
    const V3 t2 = cross(wh, t1);
    const float r = std::sqrt(u0);
    const float p1 = r * cos_p;
    const float s = 0.5f * (1.f + wh.z);
    const float p2 = (1.f - s) * std::sqrt(std::max(1.f - p1 * p1, 0.f)) + s * (r * sin_p);
    const float pz = std::sqrt(std::max((1.f - p1 * p1) - p2 * p2, 0.f));
    const V3 nh = (t1 * p1 + t2 * p2) + wh * pz;
    const V3 hs{g.nu * nh.x, g.nv * nh.y, std::max(nh.z, 1e-6f)};
    return hs * (1.f / std::sqrt(dot(hs, hs)));
}

inline void glossy_eval(const GlossyLane& g, V3 wo, V3 wi, V3& f, float& pdf) {
    f = V3{0.f, 0.f, 0.f};
    pdf = 0.f;
    if (!(wo.z > 0.f && wi.z > 0.f)) return;
    if (g.kind == kGlossPhong) {
        const float c = (-wo.x * wi.x + -wo.y * wi.y) + wo.z * wi.z;
        if (!(c > 0.f)) return;
        const float pw = pow_poly(c, g.nu);
        f = g.color * (((g.nu + 2.f) * 0.5f) * kDiffuseInvPi * pw);
        pdf = ((g.nu + 1.f) * 0.5f) * kDiffuseInvPi * pw;
    } else if (g.microfacet()) {
        const V3 hv = wo + wi;
        const V3 h = hv * (1.f / std::sqrt(dot(hv, hv)));
        const float oh_signed = dot(wo, h);
        const float oh = std::fabs(oh_signed);
        const float kg = 2.f * std::fabs(h.z) / oh;
        const float gv =
            oh == 0.f ? 0.f : std::min(std::min(1.f, kg * std::fabs(wo.z)), kg * std::fabs(wi.z));
        const V3 fr = glossy_fresnel(g, dot(wi, h));
        const float d = glossy_d(g, h);
        float shadowing = gv;
        pdf = (d * std::fabs(h.z)) / (4.f * oh_signed);
        if (g.kind == kGlossGgx) {
            const float lo = ggx_lambda(g, wo), li = ggx_lambda(g, wi);
            shadowing = 1.f / ((1.f + lo) + li);
            pdf = ((1.f / (1.f + lo)) * d) / (4.f * wo.z);
        }
        const float kf = d * shadowing / ((4.f * wo.z) * wi.z);
        f = V3{(g.color.x * fr.x) * kf, (g.color.y * fr.y) * kf, (g.color.z * fr.z) * kf};
    }
}

// The sampled local direction; false where the lobe gives none.
inline bool glossy_sample(const GlossyLane& g, V3 wo, float u0, float u1, V3& wi) {
    if (!(wo.z > 0.f)) return false;
    float sin_p, cos_p;
    sincos_turn(u1, sin_p, cos_p);
    if (g.kind == kGlossPhong) {
        const V3 m{-wo.x, -wo.y, wo.z};
        const float ca = pow_poly(u0, 1.f / (g.nu + 1.f));
        const float sa = std::sqrt(std::max(0.f, 1.f - ca * ca));
        V3 fs, ft;
        shading_frame(m, fs, ft);
        wi = (fs * (sa * cos_p) + ft * (sa * sin_p)) + m * ca;
        return wi.z > 0.f;
    }
    float cp = cos_p, sp = sin_p, cos_t;
    if (g.kind == kGlossGgx) {
        cos_t = 1.f;  // the visible normal below
    } else if (g.kind == kGlossBeckmann) {
        const float tan2 = (-g.nu * g.nu) * log_poly(1.f - u0);
        cos_t = 1.f / std::sqrt(1.f + tan2);
    } else {
        if (g.nu != g.nv) {
            const float q = 4.f * u1;
            const float quadrant = (float(q >= 1.f) + float(q >= 2.f)) + float(q >= 3.f);
            float sx, cx;
            sincos_turn((q - quadrant) * 0.25f, sx, cx);
            const float r = std::sqrt((g.nu + 2.f) / (g.nv + 2.f));
            const float rs = r * sx;
            const float inv = 1.f / std::sqrt(cx * cx + rs * rs);
            const float cb = cx * inv, sb = rs * inv;
            cp = quadrant == 1.f || quadrant == 2.f ? -cb : cb;
            sp = quadrant == 2.f || quadrant == 3.f ? -sb : sb;
        }
        const float e = g.nu * cp * cp + g.nv * sp * sp;
        cos_t = pow_poly(u0, 1.f / (e + 2.f));
    }
    const float sin_t = std::sqrt(std::max(0.f, 1.f - cos_t * cos_t));
    V3 h{sin_t * cp, sin_t * sp, cos_t};
    if (g.kind == kGlossGgx) h = ggx_visible_normal(g, wo, u0, sin_p, cos_p);
    const float oh = dot(wo, h);
    if (!(oh > 0.f)) return false;
    wi = h * (2.f * oh) - wo;
    return wi.z > 0.f;
}

}  // namespace foton::kern::scalar
