// A rough dielectric interface (Walter, Marschner, Li and Torrance, "Microfacet models for
// refraction through rough surfaces", EGSR 2007), with Trowbridge–Reitz normals sampled as
// seen from wo (Heitz 2018) and Smith's height-correlated shadowing, as pbrt-v4's rough
// DielectricBxDF and the field use it: rough glass, frosted windows, pbrt-v4's
// `dielectric` with roughness.
//
// Local directions, z the shading normal, which faces the arriving ray. The side wo lies on
// is the incident medium: index 1 when the ray arrived at the geometry's front (ctx.front)
// and wo is on its side (z > 0), ior behind it; a wo below the surface (the reverse
// densities of bidirectional MIS, pdf(wi, wo) with wi transmitted) is in the other medium.
// eta = eta_t / eta_i. With the generalised half vector wm (wo + wi for reflection, wo + eta wi for
// refraction, turned to z > 0):
//   reflection   f = tint_r D G F / (4 |cos_o cos_i|),
//   transmission f = tint_t D G (1 - F) |wi.wm| |wo.wm| / (|cos_o cos_i| (wi.wm + wo.wm / eta)^2)
//                    (over eta^2 when radiance flows: Veach's non-symmetric refraction),
// sampled by choosing reflection with probability F, each with the visible-normal density
// and the half vector's Jacobian. Restricted to one branch (`only`: a layered lobe's walk asks
// for the coat's transmission alone, then its reflection alone), the branch is always taken
// and its density is no longer multiplied by F or 1 - F.
#include <cmath>

#include "bsdf.h"
#include "engine/core/optics.h"

namespace foton {

namespace {

// A direction pair seen from wo's side (both turned so that wo.z > 0), the indices on either
// side and the generalised half vector joining them.
struct HalfVector {
    Vec3 wo, wi, wm;
    float eta_i, eta_t, eta;  // eta = eta_t / eta_i
    bool reflect;
};

bool half_vector(const Lobe& l, Vec3 wo, Vec3 wi, const BsdfContext& ctx, HalfVector& h) {
    if (wo.z == 0.f || wi.z == 0.f) return false;
    bool front = ctx.front;
    if (wo.z < 0.f) {
        wo = -wo;
        wi = -wi;
        front = !front;
    }
    h.eta_i = front ? 1.f : l.fresnel.ior;
    h.eta_t = front ? l.fresnel.ior : 1.f;
    h.eta = h.eta_t / h.eta_i;
    h.reflect = wi.z > 0.f;
    const Vec3 m = h.reflect ? wo + wi : wo + wi * h.eta;
    if (length_squared(m) == 0.f) return false;
    h.wm = normalize(m);
    if (h.wm.z < 0.f) h.wm = -h.wm;
    // A microfacet seen from behind by either direction joins nothing.
    if (dot(h.wm, wi) * wi.z < 0.f || dot(h.wm, wo) * wo.z < 0.f) return false;
    h.wo = wo;
    h.wi = wi;
    return true;
}

}  // namespace

RGB rough_dielectric_f(const Lobe& l, const Vec3& wo, const Vec3& wi, const BsdfContext& ctx) {
    HalfVector h;
    if (!half_vector(l, wo, wi, ctx, h)) return RGB{0.f};
    const float om = dot(h.wo, h.wm), im = dot(h.wi, h.wm);
    const float F = fresnel_dielectric(om, h.eta_i, h.eta_t);
    const float dg = l.dist.D(h.wm) * l.dist.smith_g(h.wo, h.wi);
    if (h.reflect) return l.color * (dg * F / (4.f * h.wo.z * h.wi.z));
    const float s = im + om / h.eta;
    float t = dg * (1.f - F) * std::fabs(im * om / (h.wo.z * h.wi.z * s * s));
    if (ctx.mode == Transport::Radiance) t /= h.eta * h.eta;
    return l.transmit * t;
}

float rough_dielectric_pdf(const Lobe& l, const Vec3& wo, const Vec3& wi, const BsdfContext& ctx,
                           uint8_t only) {
    HalfVector h;
    if (!half_vector(l, wo, wi, ctx, h)) return 0.f;
    if (!(only & (h.reflect ? kReflection : kTransmission))) return 0.f;
    const float om = dot(h.wo, h.wm), im = dot(h.wi, h.wm);
    float F = fresnel_dielectric(om, h.eta_i, h.eta_t);
    if (!(only & kTransmission)) F = 1.f;
    if (!(only & kReflection)) F = 0.f;
    // The visible normals' density G1(wo) D(wm) (wo.wm) / wo.z, times the Jacobian of the
    // half vector and the probability of the branch.
    const float visible = l.dist.g1(h.wo) / h.wo.z * l.dist.D(h.wm) * om;
    if (h.reflect) return visible / (4.f * om) * F;
    const float s = im + om / h.eta;
    return visible * std::fabs(im) / (s * s) * (1.f - F);
}

bool rough_dielectric_sample(const Lobe& l, const Vec3& wo, float uc, Point2 u,
                             const BsdfContext& ctx, BsdfSample& s, uint8_t only) {
    if (wo.z == 0.f) return false;
    const float sign = wo.z < 0.f ? -1.f : 1.f;
    const Vec3 o = wo * sign;
    const bool front = wo.z < 0.f ? !ctx.front : ctx.front;
    const float eta_i = front ? 1.f : l.fresnel.ior;
    const float eta_t = front ? l.fresnel.ior : 1.f;
    const Vec3 wm = l.dist.sample_visible(o, u);
    const float om = dot(o, wm);
    if (om <= 0.f) return false;
    float F = fresnel_dielectric(om, eta_i, eta_t);
    if (!(only & kTransmission)) F = 1.f;
    if (!(only & kReflection)) F = 0.f;
    Vec3 wi;
    if (uc < F) {
        wi = wm * (2.f * om) - o;
        if (wi.z <= 0.f) return false;
        s.flags = kGlossy | kReflection;
        s.eta = 1.f;
    } else {
        if (!refract(-o, wm, eta_i / eta_t, wi) || wi.z >= 0.f) return false;
        s.flags = kGlossy | kTransmission;
        s.eta = eta_t / eta_i;
    }
    s.wi = wi * sign;
    s.pdf = rough_dielectric_pdf(l, wo, s.wi, ctx, only);
    s.f = rough_dielectric_f(l, wo, s.wi, ctx);
    return s.pdf > 0.f;
}

}  // namespace foton
