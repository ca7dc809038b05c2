// A layered lobe: a dielectric coat at height `thickness` over an opaque base at height 0,
// with an optional medium between them, evaluated by random walks through the layer
// (Guo, Hasan, Yan and Zhao, "Position-free Monte Carlo simulation for arbitrary layered
// BSDFs", 2018, in the form pbrt-v4's LayeredBxDF gives it; our own code).
//
// f(wo, wi) is estimated by walks entering through the coat along wo, joined at every base
// bounce and medium scattering to a presampled refraction of wi through the coat (next-event
// estimation, power-heuristic weighted against the walk's own next direction when both can
// reach it). The base is opaque, so a coated lobe only reflects: a walk can only leave through
// the coat. sample() follows one walk and returns its own throughput and density, whose ratio
// is an unbiased weight; pdf() is an estimate (a transmission-reflection-transmission product
// mixed with the uniform hemisphere), which is what multiple importance sampling reads.
//
// The walks' random numbers are hashed from the directions (f from wo and wi, pdf from wi and
// wo, sample from wo and its own numbers), so f and pdf are functions of their arguments and
// an image does not depend on the thread count. The lobe is two-sided: a wo below the surface
// is mirrored, as pbrt-v4 does for coateddiffuse and coatedconductor.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "bsdf.h"
#include "engine/core/optics.h"
#include "engine/core/rng.h"
#include "medium.h"

namespace foton {

namespace {

constexpr uint8_t kBoth = kReflection | kTransmission;
constexpr float kOneBelowOne = 0x1.fffffep-1f;

Transport adjoint(Transport m) {
    return m == Transport::Radiance ? Transport::Importance : Transport::Radiance;
}

uint64_t direction_bits(const Vec3& w) {
    uint32_t x, y, z;
    std::memcpy(&x, &w.x, 4);
    std::memcpy(&y, &w.y, 4);
    std::memcpy(&z, &w.z, 4);
    return rng::mix64((uint64_t(x) << 32 | y) ^ rng::mix64(z + 0x51ed27ull));
}

// The numbers of one evaluation: a counter-based stream keyed by the directions.
class WalkNumbers {
  public:
    WalkNumbers(uint64_t a, uint64_t b, uint64_t salt) : prefix_(rng::stream_prefix(a ^ salt, b)) {}
    float operator()() { return std::min(rng::uniform_from(prefix_, n_++, 0), kOneBelowOne); }
    Point2 pair() {
        const float u = (*this)();
        return {u, (*this)()};
    }

  private:
    uint64_t prefix_;
    uint64_t n_ = 0;
};

float power_heuristic(float a, float b) {
    const float a2 = a * a, b2 = b * b;
    return a2 + b2 > 0.f ? a2 / (a2 + b2) : 0.f;
}

// Transmittance across a height difference dz along w (unit extinction).
float layer_tr(float dz, const Vec3& w) {
    if (std::fabs(dz) <= 1e-30f) return 1.f;
    return std::exp(-std::fabs(dz / w.z));
}

// The coat and the base as lobes of their own. The coat is untinted; the side of the coat a
// direction is on is the sign of its z (above: outside, index 1).
struct Stack {
    Lobe top, bottom;
    explicit Stack(const Lobe& l) {
        const CoatLayer& c = l.coat;
        top = c.coat_smooth ? Lobe::dielectric(c.ior, RGB{1.f}, RGB{1.f})
                            : Lobe::rough_dielectric(c.ior, c.coat, RGB{1.f}, RGB{1.f});
        if (c.base == CoatBase::Diffuse)
            bottom = Lobe::lambert(l.color);
        else if (c.base_smooth)
            bottom = Lobe::mirror(l.color, l.fresnel);
        else
            bottom = Lobe::microfacet(l.color, l.dist, l.fresnel);
    }
};

// A smooth coat sampled with its side taken from wo.z, restricted to `only`.
bool smooth_coat_sample(const Lobe& coat, const Vec3& wo, float uc, Transport mode, uint8_t only,
                        BsdfSample& s) {
    const bool outside = wo.z > 0.f;
    const float eta_i = outside ? 1.f : coat.fresnel.ior, eta_t = outside ? coat.fresnel.ior : 1.f;
    const float cos_i = std::fabs(wo.z);
    if (cos_i == 0.f) return false;
    const float F = fresnel_dielectric(cos_i, eta_i, eta_t);
    const float pr = (only & kReflection) ? F : 0.f, pt = (only & kTransmission) ? 1.f - F : 0.f;
    if (pr + pt <= 0.f) return false;
    if (uc < pr / (pr + pt)) {
        s.wi = {-wo.x, -wo.y, wo.z};
        s.f = RGB{F / cos_i};
        s.pdf = pr / (pr + pt);
        s.flags = kSpecular | kReflection;
        s.eta = 1.f;
        return true;
    }
    const Vec3 n{0.f, 0.f, outside ? 1.f : -1.f};
    Vec3 t;
    if (!refract(-wo, n, eta_i / eta_t, t)) return false;
    const float scale = mode == Transport::Radiance ? (eta_i * eta_i) / (eta_t * eta_t) : 1.f;
    s.wi = t;
    s.f = RGB{(1.f - F) * scale / std::fabs(t.z)};
    s.pdf = pt / (pr + pt);
    s.flags = kSpecular | kTransmission;
    s.eta = eta_t / eta_i;
    return true;
}

// Context for the stack's own lobes: the coat's side comes from the directions' z (front),
// the base is only ever seen from above.
BsdfContext layer_ctx(Transport mode) {
    return BsdfContext{true, mode};
}

RGB iface_f(const Lobe& i, const Vec3& wo, const Vec3& wi, Transport mode) {
    return lobe_f(i, wo, wi, layer_ctx(mode));
}

float iface_pdf(const Lobe& i, const Vec3& wo, const Vec3& wi, Transport mode, uint8_t only) {
    if (i.type == LobeType::RoughDielectric)
        return rough_dielectric_pdf(i, wo, wi, layer_ctx(mode), only);
    return (only & kReflection) ? lobe_pdf(i, wo, wi, layer_ctx(mode)) : 0.f;
}

// A sample that carries something: a direction off the plane, a density and a value.
bool iface_sample(const Lobe& i, const Vec3& wo, float uc, Point2 u, Transport mode, uint8_t only,
                  BsdfSample& s) {
    bool ok;
    if (i.type == LobeType::Dielectric)
        ok = smooth_coat_sample(i, wo, uc, mode, only, s);
    else if (i.type == LobeType::RoughDielectric)
        ok = rough_dielectric_sample(i, wo, uc, u, layer_ctx(mode), s, only);
    else
        ok = (only & kReflection) && lobe_sample(i, wo, uc, u, layer_ctx(mode), s);
    return ok && s.pdf > 0.f && s.wi.z != 0.f && !s.f.is_black();
}

// The density with which the next-event direction wis (the coat's transmission sampled from
// wi) would have been -w: the other strategy's density in the MIS weight of a walk direction w
// that leaves through the coat towards wi. pbrt-v4 reads the coat's pdf the other way round
// (from -w to wi), which is not the density wis was drawn with: on a rough coat the two
// strategies' weights then do not sum to one and f comes out a few per cent high.
float nee_pdf(const Lobe& top, const Vec3& wi, const Vec3& w, Transport mode) {
    return iface_pdf(top, wi, -w, adjoint(mode), kTransmission);
}

// The walks' medium step: a free flight of unit extinction from height z along w; true when
// it scatters inside the layer (z becomes the new height), false when it reaches an
// interface (z becomes that interface's height).
bool medium_step(const CoatLayer& c, const Vec3& w, float u, float& z) {
    const float dz = -std::log1p(-u) * std::fabs(w.z);
    const float zp = w.z > 0.f ? z + dz : z - dz;
    if (zp > 0.f && zp < c.thickness) {
        z = zp;
        return true;
    }
    z = w.z > 0.f ? c.thickness : 0.f;
    return false;
}

}  // namespace

RGB coated_f(const Lobe& l, const Vec3& wo_in, const Vec3& wi_in, const BsdfContext& ctx) {
    const CoatLayer& c = l.coat;
    const Vec3 wo = wo_in.z < 0.f ? -wo_in : wo_in, wi = wo_in.z < 0.f ? -wi_in : wi_in;
    // The base is opaque: nothing leaves on the far side.
    if (wo.z == 0.f || wi.z <= 0.f) return RGB{0.f};
    const Stack st(l);
    const bool top_specular = st.top.is_delta(), base_specular = st.bottom.is_delta();
    const bool medium = !c.albedo.is_black();
    const Transport mode = ctx.mode;
    const int samples = std::max(1, int(c.samples));
    RGB f = iface_f(st.top, wo, wi, mode) * float(samples);
    WalkNumbers r(direction_bits(wo), direction_bits(wi), 0x6c617965ull);
    for (int n = 0; n < samples; ++n) {
        BsdfSample wos, wis;
        if (!iface_sample(st.top, wo, r(), r.pair(), mode, kTransmission, wos)) continue;
        if (!iface_sample(st.top, wi, r(), r.pair(), adjoint(mode), kTransmission, wis)) continue;
        RGB beta = wos.f * (std::fabs(wos.wi.z) / wos.pdf);
        float z = c.thickness;
        Vec3 w = wos.wi;
        for (int depth = 0; depth < c.max_depth; ++depth) {
            if (depth > 3 && beta.max_component() < 0.25f) {
                const float q = std::max(0.f, 1.f - beta.max_component());
                if (r() < q) break;
                beta *= 1.f / (1.f - q);
            }
            if (!medium) {
                z = z == c.thickness ? 0.f : c.thickness;
                beta *= layer_tr(c.thickness, w);
            } else if (medium_step(c, w, r(), z)) {
                // Scattered in the medium: join to wi through the coat, then scatter on.
                const float to_exit = z - c.thickness;
                const float phase_nee = henyey_greenstein(dot(-w, -wis.wi), c.g);
                const float wt_nee = top_specular ? 1.f : power_heuristic(wis.pdf, phase_nee);
                f += beta * c.albedo * wis.f *
                     (phase_nee * wt_nee * layer_tr(to_exit, wis.wi) / wis.pdf);
                Vec3 next;
                const float p = sample_henyey_greenstein(-w, c.g, r.pair(), next);
                if (!(p > 0.f) || next.z == 0.f) continue;
                beta *= c.albedo;  // the phase function is its own density
                w = next;
                if (w.z > 0.f && !top_specular) {
                    const RGB f_exit = iface_f(st.top, -w, wi, mode);
                    if (!f_exit.is_black()) {
                        const float wt = power_heuristic(p, nee_pdf(st.top, wi, w, mode));
                        f += beta * f_exit * (layer_tr(to_exit, w) * wt);
                    }
                }
                continue;
            }
            BsdfSample bs;
            if (z == c.thickness) {
                // Back down off the underside of the coat.
                if (!iface_sample(st.top, -w, r(), r.pair(), mode, kReflection, bs)) break;
                beta *= bs.f * (std::fabs(bs.wi.z) / bs.pdf);
                w = bs.wi;
                continue;
            }
            // At the base: join to wi through the coat, then bounce.
            if (!base_specular) {
                const float wt =
                    top_specular
                        ? 1.f
                        : power_heuristic(wis.pdf, iface_pdf(st.bottom, -w, -wis.wi, mode, kBoth));
                f += beta * iface_f(st.bottom, -w, -wis.wi, mode) * wis.f *
                     (std::fabs(wis.wi.z) * wt * layer_tr(c.thickness, wis.wi) / wis.pdf);
            }
            if (!iface_sample(st.bottom, -w, r(), r.pair(), mode, kReflection, bs)) break;
            beta *= bs.f * (std::fabs(bs.wi.z) / bs.pdf);
            w = bs.wi;
            if (!top_specular) {
                const RGB f_exit = iface_f(st.top, -w, wi, mode);
                if (!f_exit.is_black()) {
                    const float wt =
                        base_specular ? 1.f : power_heuristic(bs.pdf, nee_pdf(st.top, wi, w, mode));
                    f += beta * f_exit * (layer_tr(c.thickness, bs.wi) * wt);
                }
            }
        }
    }
    return f * (c.weight / float(samples));
}

bool coated_sample(const Lobe& l, const Vec3& wo_in, float uc, Point2 u, const BsdfContext& ctx,
                   BsdfSample& s) {
    const CoatLayer& c = l.coat;
    const bool flip = wo_in.z < 0.f;
    const Vec3 wo = flip ? -wo_in : wo_in;
    if (wo.z == 0.f) return false;
    const Stack st(l);
    const Transport mode = ctx.mode;
    BsdfSample bs;
    if (!iface_sample(st.top, wo, uc, u, mode, kBoth, bs)) return false;
    if (bs.wi.z > 0.f) {
        // Reflected by the coat itself.
        s = bs;
        s.f *= c.weight;
        if (flip) s.wi = -s.wi;
        return true;
    }
    Vec3 w = bs.wi;
    bool specular = bs.is_delta();
    RGB f = bs.f * std::fabs(bs.wi.z);
    float pdf = bs.pdf;
    float z = c.thickness;
    const bool medium = !c.albedo.is_black();
    uint32_t ubits;
    std::memcpy(&ubits, &uc, 4);
    uint64_t sample_bits = rng::mix64(uint64_t(ubits) ^ direction_bits({u.x, u.y, 0.f}));
    WalkNumbers r(direction_bits(wo), sample_bits, 0x73616d70ull);
    for (int depth = 0; depth < c.max_depth; ++depth) {
        const float rr = f.max_component() / pdf;
        if (depth > 3 && rr < 0.25f) {
            const float q = std::max(0.f, 1.f - rr);
            if (r() < q) return false;
            pdf *= 1.f - q;
        }
        if (w.z == 0.f) return false;
        if (!medium) {
            z = z == c.thickness ? 0.f : c.thickness;
            f *= layer_tr(c.thickness, w);
        } else if (medium_step(c, w, r(), z)) {
            Vec3 next;
            const float p = sample_henyey_greenstein(-w, c.g, r.pair(), next);
            if (!(p > 0.f) || next.z == 0.f) return false;
            f *= c.albedo * p;
            pdf *= p;
            specular = false;
            w = next;
            continue;
        }
        const Lobe& iface = z == 0.f ? st.bottom : st.top;
        if (!iface_sample(iface, -w, r(), r.pair(), mode, kBoth, bs)) return false;
        f *= bs.f;
        pdf *= bs.pdf;
        specular = specular && bs.is_delta();
        w = bs.wi;
        if (bs.flags & kTransmission) {
            // Out through the coat: a reflection of the whole stack.
            s.wi = flip ? -w : w;
            s.f = f * c.weight;
            s.pdf = pdf;
            s.flags = uint8_t(kReflection | (specular ? kSpecular : kGlossy));
            s.eta = 1.f;
            return pdf > 0.f;
        }
        f *= std::fabs(bs.wi.z);
    }
    return false;
}

float coated_pdf(const Lobe& l, const Vec3& wo_in, const Vec3& wi_in, const BsdfContext& ctx) {
    const CoatLayer& c = l.coat;
    const Vec3 wo = wo_in.z < 0.f ? -wo_in : wo_in, wi = wo_in.z < 0.f ? -wi_in : wi_in;
    if (wo.z == 0.f || wi.z <= 0.f) return 0.f;
    const Stack st(l);
    const Transport mode = ctx.mode;
    const int samples = std::max(1, int(c.samples));
    float sum = float(samples) * iface_pdf(st.top, wo, wi, mode, kReflection);
    WalkNumbers r(direction_bits(wi), direction_bits(wo), 0x70646621ull);
    for (int n = 0; n < samples; ++n) {
        // Transmission in, a base reflection, transmission out.
        BsdfSample wos, wis;
        if (!iface_sample(st.top, wo, r(), r.pair(), mode, kTransmission, wos)) continue;
        if (!iface_sample(st.top, wi, r(), r.pair(), adjoint(mode), kTransmission, wis)) continue;
        if (st.top.is_delta()) {
            sum += iface_pdf(st.bottom, -wos.wi, -wis.wi, mode, kBoth);
            continue;
        }
        BsdfSample rs;
        if (!iface_sample(st.bottom, -wos.wi, r(), r.pair(), mode, kBoth, rs)) continue;
        if (st.bottom.is_delta()) {
            sum += iface_pdf(st.top, -rs.wi, wi, mode, kBoth);
            continue;
        }
        const float r_pdf = iface_pdf(st.bottom, -wos.wi, -wis.wi, mode, kBoth);
        sum += power_heuristic(wis.pdf, r_pdf) * r_pdf;
        const float t_pdf = iface_pdf(st.top, -rs.wi, wi, mode, kBoth);
        sum += power_heuristic(rs.pdf, t_pdf) * t_pdf;
    }
    // Mixed with the uniform hemisphere: never zero where f may not be.
    return 0.1f / (2.f * kPi) + 0.9f * sum / float(samples);
}

RGB coated_mirror_weight(const Lobe& l, const Vec3& wo_in) {
    const CoatLayer& c = l.coat;
    if (!c.coat_smooth) return RGB{0.f};
    const float cos_o = std::fabs(wo_in.z);
    if (cos_o == 0.f) return RGB{0.f};
    const float F = fresnel_dielectric(cos_o, 1.f, c.ior);
    if (!l.coat_is_delta()) return RGB{F * c.weight};
    // Inside, along the refracted direction: the base's reflectance Rb, the coat's inner
    // reflectance (F again, by reciprocity) and the layer's transmittance each way. The
    // radiance scalings of entering and leaving cancel.
    const float sin2 = std::max(0.f, 1.f - cos_o * cos_o) / (c.ior * c.ior);
    const float cos_t = std::sqrt(std::max(0.f, 1.f - sin2));
    const float tr = layer_tr(c.thickness, {0.f, 0.f, cos_t});
    const RGB rb = l.color * l.fresnel.eval(cos_t);
    RGB out;
    for (int ch = 0; ch < 3; ++ch) {
        const float b = (&rb.r)[ch] * tr * tr;
        (&out.r)[ch] = F + (1.f - F) * (1.f - F) * b / (1.f - F * b);
    }
    return out * c.weight;
}

}  // namespace foton
