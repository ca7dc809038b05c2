#include "bsdf.h"

#include <algorithm>
#include <cmath>

#include "engine/core/optics.h"
#include "engine/core/warp.h"

namespace foton {

namespace {

bool same_side(const Vec3& a, const Vec3& b) {
    return a.z * b.z > 0.f;
}

// Mirror of wo about the local normal.
Vec3 mirror_dir(const Vec3& wo) {
    return {-wo.x, -wo.y, wo.z};
}

// The sampling weight of a lobe: its colour's luminance (the Fresnel term is left out so that
// a plastic's highlight is not starved by its 4 % normal-incidence reflectance).
float sampling_weight(const Lobe& l) {
    // A coat reflects at least its Fresnel share even over a black base.
    if (l.type == LobeType::Coated)
        return l.coat.weight > 0.f ? std::max(l.color.luminance(), 0.05f) * l.coat.weight : 0.f;
    const float w = l.flags() & kTransmission
                        ? std::max(l.color.luminance(), l.transmit.luminance())
                        : l.color.luminance();
    return w > 0.f ? std::max(w, 1e-3f) : 0.f;
}

}  // namespace

RGB lobe_f(const Lobe& l, const Vec3& wo, const Vec3& wi, const BsdfContext& ctx) {
    switch (l.type) {
        case LobeType::Lambert:
            return same_side(wo, wi) ? l.color * kInvPi : RGB{0.f};
        case LobeType::OrenNayar: {
            if (!same_side(wo, wi)) return RGB{0.f};
            const float ci = std::fabs(wi.z), co = std::fabs(wo.z);
            const float si = std::sqrt(std::max(0.f, 1.f - ci * ci));
            const float so = std::sqrt(std::max(0.f, 1.f - co * co));
            float cos_dphi = 0.f;
            if (si > 1e-4f && so > 1e-4f)
                cos_dphi = std::max(0.f, (wi.x * wo.x + wi.y * wo.y) / (si * so));
            // alpha = the larger polar angle, beta = the smaller.
            const float sin_alpha = ci > co ? so : si;
            const float tan_beta = ci > co ? si / ci : so / co;
            return l.color * (kInvPi * (l.on_a + l.on_b * cos_dphi * sin_alpha * tan_beta));
        }
        case LobeType::Phong: {
            if (wo.z <= 0.f || wi.z <= 0.f) return RGB{0.f};
            const float c = dot(mirror_dir(wo), wi);
            if (c <= 0.f) return RGB{0.f};
            return l.color * ((l.exponent + 2.f) * 0.5f * kInvPi * std::pow(c, l.exponent));
        }
        case LobeType::Microfacet: {
            if (wo.z <= 0.f || wi.z <= 0.f) return RGB{0.f};
            const Vec3 h = normalize(wo + wi);
            const float g =
                l.dist.visible_normals() ? l.dist.smith_g(wo, wi) : vcavity_g(wo, wi, h);
            return l.color * l.fresnel.eval(dot(wi, h)) * (l.dist.D(h) * g / (4.f * wo.z * wi.z));
        }
        case LobeType::LambertTransmission:
            return !same_side(wo, wi) && wi.z != 0.f ? l.color * kInvPi : RGB{0.f};
        case LobeType::SubsurfaceExit: {
            if (!same_side(wo, wi)) return RGB{0.f};
            const float eta = l.fresnel.ior;
            const float t = 1.f - fresnel_dielectric(std::fabs(wi.z), 1.f, eta);
            // Radiance leaving is eta^2 times the radiance the medium carries.
            return l.color * (t * kInvPi * (ctx.mode == Transport::Radiance ? eta * eta : 1.f));
        }
        case LobeType::RoughDielectric:
            return rough_dielectric_f(l, wo, wi, ctx);
        case LobeType::Coated:
            return l.coat_is_delta() ? RGB{0.f} : coated_f(l, wo, wi, ctx);
        case LobeType::Hair:
            return ctx.mode == Transport::Importance ? hair_adjoint_f(l, wo, wi)
                                                     : hair_f(l, wo, wi);
        case LobeType::Measured:
            return measured_f(l, wo, wi);
        case LobeType::Mirror:
        case LobeType::Dielectric:
        case LobeType::ThinDielectric:
            return RGB{0.f};
    }
    return RGB{0.f};
}

float lobe_pdf(const Lobe& l, const Vec3& wo, const Vec3& wi, const BsdfContext& ctx) {
    switch (l.type) {
        case LobeType::Lambert:
        case LobeType::OrenNayar:
        case LobeType::SubsurfaceExit:
            return same_side(wo, wi) ? std::fabs(wi.z) * kInvPi : 0.f;
        case LobeType::Phong: {
            if (wo.z <= 0.f || wi.z <= 0.f) return 0.f;
            const float c = dot(mirror_dir(wo), wi);
            return c > 0.f ? (l.exponent + 1.f) * 0.5f * kInvPi * std::pow(c, l.exponent) : 0.f;
        }
        case LobeType::Microfacet: {
            if (wo.z <= 0.f || wi.z <= 0.f) return 0.f;
            const Vec3 h = normalize(wo + wi);
            // Visible normals: G1(wo) D(h) (wo.h) / wo.z, over the reflection's 4 (wo.h).
            if (l.dist.visible_normals()) return l.dist.g1(wo) * l.dist.D(h) / (4.f * wo.z);
            return l.dist.pdf_h(h) / (4.f * dot(wo, h));
        }
        case LobeType::LambertTransmission:
            return !same_side(wo, wi) && wi.z != 0.f ? std::fabs(wi.z) * kInvPi : 0.f;
        case LobeType::RoughDielectric:
            return rough_dielectric_pdf(l, wo, wi, ctx);
        case LobeType::Coated:
            return l.coat_is_delta() ? 0.f : coated_pdf(l, wo, wi, ctx);
        case LobeType::Hair:
            return hair_pdf(l, wo, wi);
        case LobeType::Measured:
            return measured_pdf(l, wo, wi);
        case LobeType::Mirror:
        case LobeType::Dielectric:
        case LobeType::ThinDielectric:
            return 0.f;
    }
    return 0.f;
}

bool lobe_sample(const Lobe& l, const Vec3& wo, float uc, Point2 u, const BsdfContext& ctx,
                 BsdfSample& s) {
    s.flags = l.flags();
    switch (l.type) {
        case LobeType::Lambert:
        case LobeType::OrenNayar:
        case LobeType::SubsurfaceExit: {
            s.wi = warp::cosine_hemisphere(u);
            if (wo.z < 0.f) s.wi.z = -s.wi.z;
            s.pdf = lobe_pdf(l, wo, s.wi, ctx);
            s.f = lobe_f(l, wo, s.wi, ctx);
            return s.pdf > 0.f;
        }
        case LobeType::Phong: {
            if (wo.z <= 0.f) return false;
            // cos(alpha) = u^(1/(n+1)) around the mirror direction: pdf (n+1)/(2 pi) cos^n.
            const float ca = std::pow(u.x, 1.f / (l.exponent + 1.f));
            const float sa = std::sqrt(std::max(0.f, 1.f - ca * ca));
            const float phi = 2.f * kPi * u.y;
            const warp::Frame fr(mirror_dir(wo));
            s.wi = fr.to_world({sa * std::cos(phi), sa * std::sin(phi), ca});
            if (s.wi.z <= 0.f) return false;
            s.pdf = lobe_pdf(l, wo, s.wi, ctx);
            s.f = lobe_f(l, wo, s.wi, ctx);
            return s.pdf > 0.f;
        }
        case LobeType::Microfacet: {
            if (wo.z <= 0.f) return false;
            const Vec3 h =
                l.dist.visible_normals() ? l.dist.sample_visible(wo, u) : l.dist.sample_h(u);
            const float oh = dot(wo, h);
            if (oh <= 0.f) return false;
            s.wi = h * (2.f * oh) - wo;
            if (s.wi.z <= 0.f) return false;
            s.pdf = lobe_pdf(l, wo, s.wi, ctx);
            s.f = lobe_f(l, wo, s.wi, ctx);
            return s.pdf > 0.f;
        }
        case LobeType::LambertTransmission: {
            // A cosine-weighted direction on the side away from wo.
            s.wi = warp::cosine_hemisphere(u);
            if (wo.z > 0.f) s.wi.z = -s.wi.z;
            s.pdf = lobe_pdf(l, wo, s.wi, ctx);
            s.f = lobe_f(l, wo, s.wi, ctx);
            s.eta = 1.f;
            return s.pdf > 0.f;
        }
        case LobeType::RoughDielectric:
            return rough_dielectric_sample(l, wo, uc, u, ctx, s);
        case LobeType::Coated:
            return coated_sample(l, wo, uc, u, ctx, s);
        case LobeType::Hair:
            return hair_sample(l, wo, uc, u, s, ctx.mode);
        case LobeType::Measured:
            return measured_sample(l, wo, u, s);
        case LobeType::ThinDielectric:
            return thin_dielectric_sample(l, wo, uc, s);
        case LobeType::Mirror: {
            s.wi = mirror_dir(wo);
            const float c = std::fabs(s.wi.z);
            if (c == 0.f) return false;
            s.f = l.color * l.fresnel.eval(c) * (1.f / c);
            s.pdf = 1.f;
            return true;
        }
        case LobeType::Dielectric: {
            // The frame's normal faces the incident side; entering when the ray hit the front.
            const float eta_i = ctx.front ? 1.f : l.fresnel.ior;
            const float eta_t = ctx.front ? l.fresnel.ior : 1.f;
            const float cos_i = std::fabs(wo.z);
            if (cos_i == 0.f) return false;
            const float F = fresnel_dielectric(cos_i, eta_i, eta_t);
            const Vec3 n{0.f, 0.f, wo.z > 0.f ? 1.f : -1.f};
            Vec3 t;
            if (uc < F || !refract(-wo, n, eta_i / eta_t, t)) {
                s.wi = mirror_dir(wo);
                s.f = l.color * (F / cos_i);
                s.pdf = F;
                s.flags = kSpecular | kReflection;
                return F > 0.f;
            }
            s.wi = t;
            const float scale =
                ctx.mode == Transport::Radiance ? (eta_i * eta_i) / (eta_t * eta_t) : 1.f;
            s.f = l.transmit * ((1.f - F) * scale / std::fabs(t.z));
            s.pdf = 1.f - F;
            s.flags = kSpecular | kTransmission;
            s.eta = eta_t / eta_i;
            return true;
        }
    }
    return false;
}

bool Bsdf::add(const Lobe& lobe) {
    if (n_ == kMaxLobes) return false;
    lobes_[std::size_t(n_)] = lobe;
    weight_[std::size_t(n_)] = sampling_weight(lobe);
    flags_ |= lobe.flags();
    if ((lobe.flags() & kTransmission) && !lobe.is_delta()) transmits_non_delta_ = true;
    if (lobe.is_stochastic()) stochastic_ = true;
    if (lobe.anisotropic()) anisotropic_ = true;
    if (lobe.dispersion.disperses()) disperses_ = true;
    ++n_;
    return true;
}

float Bsdf::continuation() const {
    RGB sum{0.f};
    for (int i = 0; i < n_; ++i) {
        const Lobe& l = lobes_[std::size_t(i)];
        if (l.type == LobeType::Coated) {
            sum += l.color * l.coat.weight;
            continue;
        }
        sum += l.flags() & kTransmission
                   ? RGB(std::max(l.color.r, l.transmit.r), std::max(l.color.g, l.transmit.g),
                         std::max(l.color.b, l.transmit.b))
                   : l.color;
    }
    return std::min(1.f, sum.max_component());
}

void Bsdf::scale(float w) {
    for (int i = 0; i < n_; ++i) scale_lobe(i, w);
}

void Bsdf::scale_lobe(int i, float w) {
    Lobe& l = lobes_[std::size_t(i)];
    if (l.type == LobeType::Coated) {
        l.coat.weight *= w;
    } else {
        l.color *= w;
        l.transmit *= w;
    }
    weight_[std::size_t(i)] = sampling_weight(l);
}

Bsdf Bsdf::with_texture(uint8_t lobes, const RGB& t) const {
    Bsdf b = *this;
    for (int i = 0; i < n_; ++i) {
        if (!(lobes & (1u << i))) continue;
        b.lobes_[std::size_t(i)].color *= t;
        b.weight_[std::size_t(i)] = sampling_weight(b.lobes_[std::size_t(i)]);
    }
    return b;
}

void Bsdf::set_param(int i, LobeParam target, float v) {
    Lobe& l = lobes_[std::size_t(i)];
    if (target == LobeParam::HairOffset) {
        l.hair.h = v;
        return;
    }
    if (target == LobeParam::Weight || target == LobeParam::WeightComplement) {
        scale_lobe(i, target == LobeParam::Weight ? v : 1.f - v);
        return;
    }
    const bool coat = target == LobeParam::CoatAlphaX || target == LobeParam::CoatAlphaY;
    MicrofacetDistribution& d = coat ? l.coat.coat : l.dist;
    if (target != LobeParam::AlphaY && target != LobeParam::CoatAlphaY) d.alpha = v;
    if (target != LobeParam::AlphaX && target != LobeParam::CoatAlphaX) d.alpha_y = v;
}

float Bsdf::weight_sum(uint8_t only) const {
    float sum = 0.f;
    for (int i = 0; i < n_; ++i)
        if (lobes_[std::size_t(i)].flags() & only) sum += weight_[std::size_t(i)];
    return sum;
}

RGB Bsdf::f_restricted(const Vec3& wo, const Vec3& wi, const BsdfContext& ctx, uint8_t only) const {
    RGB sum;
    for (int i = 0; i < n_; ++i) {
        const Lobe& l = lobes_[std::size_t(i)];
        if (!l.is_delta() && (l.flags() & only)) sum += lobe_f(l, wo, wi, ctx);
    }
    return sum;
}

float Bsdf::pdf_restricted(const Vec3& wo, const Vec3& wi, const BsdfContext& ctx,
                           uint8_t only) const {
    const float total = weight_sum(only);
    if (total <= 0.f) return 0.f;
    float sum = 0.f;
    for (int i = 0; i < n_; ++i) {
        const Lobe& l = lobes_[std::size_t(i)];
        if (!l.is_delta() && (l.flags() & only))
            sum += weight_[std::size_t(i)] * lobe_pdf(l, wo, wi, ctx);
    }
    return sum / total;
}

RGB Bsdf::f(const Vec3& wo, const Vec3& wi, const BsdfContext& ctx) const {
    return f_restricted(wo, wi, ctx, 0xff);
}

float Bsdf::pdf(const Vec3& wo, const Vec3& wi, const BsdfContext& ctx) const {
    return pdf_restricted(wo, wi, ctx, 0xff);
}

bool Bsdf::sample(const Vec3& wo, float uc, Point2 u, const BsdfContext& ctx, BsdfSample& s,
                  uint8_t only) const {
    const float total = weight_sum(only);
    if (total <= 0.f) return false;
    // Choose a lobe with uc and stretch the rest of uc back to [0, 1) for the lobe itself.
    float target = uc * total, acc = 0.f;
    int chosen = -1;
    for (int i = 0; i < n_; ++i) {
        if (!(lobes_[std::size_t(i)].flags() & only) || weight_[std::size_t(i)] <= 0.f) continue;
        chosen = i;
        if (target < acc + weight_[std::size_t(i)]) break;
        acc += weight_[std::size_t(i)];
    }
    if (chosen < 0) return false;
    const float w = weight_[std::size_t(chosen)];
    const float uc2 = std::clamp((target - acc) / w, 0.f, 0x1.fffffep-1f);
    const Lobe& l = lobes_[std::size_t(chosen)];
    if (!lobe_sample(l, wo, uc2, u, ctx, s)) return false;
    if (l.is_delta() || (stochastic_ && s.is_delta())) {
        s.pdf *= w / total;
        return s.pdf > 0.f;
    }
    if (stochastic_) {
        // A walk's density is not known in closed form, so the sample is weighted as the
        // chosen lobe's alone over the probability of choosing it (f |cos| / pdf stays that),
        // and reports the mixture's estimated density, which is what MIS compares.
        const float mis = pdf_restricted(wo, s.wi, ctx, only);
        if (!(mis > 0.f)) return false;
        s.f *= mis / (s.pdf * (w / total));
        s.pdf = mis;
        return true;
    }
    s.f = f_restricted(wo, s.wi, ctx, only);
    s.pdf = pdf_restricted(wo, s.wi, ctx, only);
    return s.pdf > 0.f;
}

int Bsdf::specular_directions(const Vec3& wo, const BsdfContext& ctx, Vec3* dirs, RGB* weights,
                              int max_out) const {
    int k = 0;
    for (int i = 0; i < n_ && k < max_out; ++i) {
        const Lobe& l = lobes_[std::size_t(i)];
        if (l.type == LobeType::Mirror) {
            dirs[k] = mirror_dir(wo);
            weights[k++] = l.color * l.fresnel.eval(std::fabs(wo.z));
        } else if (l.type == LobeType::Coated && l.coat.coat_smooth) {
            // The smooth coat's mirror reflection (the whole stack's, when it is all specular).
            dirs[k] = mirror_dir(wo);
            weights[k++] = coated_mirror_weight(l, wo);
        } else if (l.type == LobeType::Dielectric || l.type == LobeType::ThinDielectric) {
            // Both branches: uc = 0 forces reflection, uc -> 1 refraction (unless TIR).
            BsdfSample r, t;
            if (lobe_sample(l, wo, 0.f, {}, ctx, r) && r.pdf > 0.f) {
                dirs[k] = r.wi;
                weights[k++] = r.f * std::fabs(r.wi.z);
            }
            if (k < max_out && lobe_sample(l, wo, 0x1.fffffep-1f, {}, ctx, t) &&
                (t.flags & kTransmission)) {
                dirs[k] = t.wi;
                weights[k++] = t.f * std::fabs(t.wi.z);
            }
        }
    }
    return k;
}

}  // namespace foton
