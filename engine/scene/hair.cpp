// The hair BSDF of Chiang et al. 2016 (pbrt-v4's HairBxDF, our code). In the lobe's frame x runs
// along the fibre (SurfacePoint::ss, the curve's dp/du), so sin(theta) = w.x and the azimuth is
// atan2(w.z, w.y). Light leaves after p internal paths: R (p = 0), TT, TRT and the rest together;
// each p is a longitudinal lobe M_p (a von Mises-Fisher-like function of width v_p, shifted by
// the scales' tilt 2^k alpha) times the attenuation A_p (Fresnel and absorption along the
// refracted path) times an azimuthal lobe N_p (a trimmed logistic around the deflection of a
// smooth cylinder). f divides by |cos theta_i|, as the BSDF's cosine multiplies it back. The
// model is not reciprocal, so importance (light paths) takes its adjoint, f(wi, wo), with the
// ribbon's cosine made the fibre's (hair_adjoint_f).
#include <algorithm>
#include <array>
#include <cmath>

#include "bsdf.h"
#include "engine/core/optics.h"

namespace foton {

namespace {

constexpr int kPMax = 3;

template <class F>
RGB per_channel(const RGB& a, F&& f) {
    return {f(a.r), f(a.g), f(a.b)};
}

float safe_sqrt(float x) {
    return std::sqrt(std::max(0.f, x));
}
float safe_asin(float x) {
    return std::asin(std::clamp(x, -1.f, 1.f));
}

// Modified Bessel function of the first kind, order 0 (its series), and its logarithm.
float bessel_i0(float x) {
    float sum = 0.f, term_x = 1.f, fact = 1.f, four = 1.f;
    for (int i = 0; i < 10; ++i) {
        if (i > 1) fact *= float(i);
        sum += term_x / (four * fact * fact);
        term_x *= x * x;
        four *= 4.f;
    }
    return sum;
}
float log_bessel_i0(float x) {
    if (x > 12.f) return x + 0.5f * (-std::log(2.f * kPi) + std::log(1.f / x) + 1.f / (8.f * x));
    return std::log(bessel_i0(x));
}

float logistic(float x, float s) {
    x = std::fabs(x);
    const float e = std::exp(-x / s);
    return e / (s * (1.f + e) * (1.f + e));
}
float logistic_cdf(float x, float s) {
    return 1.f / (1.f + std::exp(-x / s));
}
float trimmed_logistic(float x, float s) {
    return logistic(x, s) / (logistic_cdf(kPi, s) - logistic_cdf(-kPi, s));
}
float sample_trimmed_logistic(float u, float s) {
    const float k = logistic_cdf(kPi, s) - logistic_cdf(-kPi, s);
    const float x = -s * std::log(1.f / (u * k + logistic_cdf(-kPi, s)) - 1.f);
    return std::clamp(x, -kPi, kPi);
}

// What one fibre's parameters derive (pbrt-v4 computes them once per BxDF).
struct Derived {
    float v[kPMax + 1];
    float s;
    float sin2k[kPMax], cos2k[kPMax];
    explicit Derived(const HairFiber& h) {
        const float bm = h.beta_m, bn = h.beta_n;
        const float v0 = 0.726f * bm + 0.812f * bm * bm + 3.7f * std::pow(bm, 20.f);
        v[0] = v0 * v0;
        v[1] = 0.25f * v[0];
        v[2] = 4.f * v[0];
        v[3] = v[2];
        s = 0.626657069f * (0.265f * bn + 1.194f * bn * bn + 5.372f * std::pow(bn, 22.f));
        sin2k[0] = std::sin(h.alpha_degrees * kPi / 180.f);
        cos2k[0] = safe_sqrt(1.f - sin2k[0] * sin2k[0]);
        for (int i = 1; i < kPMax; ++i) {
            sin2k[i] = 2.f * cos2k[i - 1] * sin2k[i - 1];
            cos2k[i] = cos2k[i - 1] * cos2k[i - 1] - sin2k[i - 1] * sin2k[i - 1];
        }
    }
    // theta_o tilted by the scales for path p: R by -2 alpha, TT by alpha, TRT by 4 alpha.
    void tilt(int p, float sin_o, float cos_o, float& sin_p, float& cos_p) const {
        if (p == 0) {
            sin_p = sin_o * cos2k[1] - cos_o * sin2k[1];
            cos_p = cos_o * cos2k[1] + sin_o * sin2k[1];
        } else if (p == 1) {
            sin_p = sin_o * cos2k[0] + cos_o * sin2k[0];
            cos_p = cos_o * cos2k[0] - sin_o * sin2k[0];
        } else if (p == 2) {
            sin_p = sin_o * cos2k[2] + cos_o * sin2k[2];
            cos_p = cos_o * cos2k[2] - sin_o * sin2k[2];
        } else {
            sin_p = sin_o;
            cos_p = cos_o;
        }
        cos_p = std::fabs(cos_p);
    }
};

float longitudinal(float cos_i, float cos_o, float sin_i, float sin_o, float v) {
    const float a = cos_i * cos_o / v, b = sin_i * sin_o / v;
    if (v <= 0.1f)
        return std::exp(log_bessel_i0(a) - b - 1.f / v + 0.6931f + std::log(1.f / (2.f * v)));
    return std::exp(-b) * bessel_i0(a) / (std::sinh(1.f / v) * 2.f * v);
}

float deflection(int p, float gamma_o, float gamma_t) {
    return 2.f * float(p) * gamma_t - 2.f * gamma_o + float(p) * kPi;
}

float azimuthal(float phi, int p, float s, float gamma_o, float gamma_t) {
    float d = phi - deflection(p, gamma_o, gamma_t);
    d = std::remainder(d, 2.f * kPi);  // to [-pi, pi]
    return trimmed_logistic(d, s);
}

// The refracted path's terms for a given theta_o: gamma_t and the attenuation per p.
struct Refraction {
    float gamma_t;
    std::array<RGB, kPMax + 1> ap;
    Refraction(const HairFiber& h, float sin_o, float cos_o) {
        const float sin_t = sin_o / h.eta, cos_t = safe_sqrt(1.f - sin_t * sin_t);
        const float etap = safe_sqrt(h.eta * h.eta - sin_o * sin_o) / cos_o;
        const float sin_gt = h.h / etap, cos_gt = safe_sqrt(1.f - sin_gt * sin_gt);
        gamma_t = safe_asin(sin_gt);
        const float length = 2.f * cos_gt / cos_t;
        const RGB T = per_channel(h.sigma_a, [&](float a) { return std::exp(-a * length); });
        const float f = fresnel_dielectric(cos_o * safe_sqrt(1.f - h.h * h.h), 1.f, h.eta);
        ap[0] = RGB{f};
        ap[1] = T * ((1.f - f) * (1.f - f));
        for (int p = 2; p < kPMax; ++p) ap[std::size_t(p)] = ap[std::size_t(p - 1)] * T * f;
        // The rest: a geometric series of ratio T f.
        const RGB tf = T * f;
        ap[kPMax] =
            ap[kPMax - 1] * per_channel(tf, [](float x) { return x < 1.f ? x / (1.f - x) : 0.f; });
    }
    std::array<float, kPMax + 1> pdf() const {
        std::array<float, kPMax + 1> out{};
        float sum = 0.f;
        for (const RGB& a : ap) sum += (a.r + a.g + a.b) / 3.f;
        for (std::size_t p = 0; p <= kPMax; ++p)
            out[p] = sum > 0.f ? (ap[p].r + ap[p].g + ap[p].b) / 3.f / sum : 0.f;
        return out;
    }
};

// Sum over p of M_p x weight_p x N_p (the rest term uniform in azimuth).
template <class Weight>
auto hair_sum(const HairFiber& h, const Derived& d, const Vec3& wo, const Vec3& wi,
              const Refraction& r, Weight&& weight) {
    const float sin_o = std::clamp(wo.x, -1.f, 1.f), cos_o = safe_sqrt(1.f - sin_o * sin_o);
    const float sin_i = std::clamp(wi.x, -1.f, 1.f), cos_i = safe_sqrt(1.f - sin_i * sin_i);
    const float phi = std::atan2(wi.z, wi.y) - std::atan2(wo.z, wo.y);
    const float gamma_o = safe_asin(h.h);
    decltype(weight(0)) sum{};
    for (int p = 0; p < kPMax; ++p) {
        float sin_p, cos_p;
        d.tilt(p, sin_o, cos_o, sin_p, cos_p);
        sum += weight(p) * (longitudinal(cos_i, cos_p, sin_i, sin_p, d.v[p]) *
                            azimuthal(phi, p, d.s, gamma_o, r.gamma_t));
    }
    sum += weight(kPMax) * (longitudinal(cos_i, cos_o, sin_i, sin_o, d.v[kPMax]) / (2.f * kPi));
    return sum;
}

// What depends on the fibre and wo alone, made once per evaluation or sample.
struct FibreAt {
    const HairFiber& h;
    Derived d;
    float sin_o, cos_o;
    Refraction r;
    FibreAt(const HairFiber& fibre, const Vec3& wo)
        : h(fibre),
          d(fibre),
          sin_o(std::clamp(wo.x, -1.f, 1.f)),
          cos_o(safe_sqrt(1.f - sin_o * sin_o)),
          r(fibre, sin_o, cos_o) {}
    RGB f(const Vec3& wo, const Vec3& wi) const {
        RGB v = hair_sum(h, d, wo, wi, r, [&](int p) { return r.ap[std::size_t(p)]; });
        return std::fabs(wi.z) > 0.f ? v * (1.f / std::fabs(wi.z)) : v;
    }
    float pdf(const std::array<float, kPMax + 1>& ap, const Vec3& wo, const Vec3& wi) const {
        return hair_sum(h, d, wo, wi, r, [&](int p) { return ap[std::size_t(p)]; });
    }
};

}  // namespace

RGB hair_f(const Lobe& l, const Vec3& wo, const Vec3& wi) {
    return FibreAt(l.hair, wo).f(wo, wi) * l.color;
}

RGB hair_adjoint_f(const Lobe& l, const Vec3& wo, const Vec3& wi) {
    // Importance arrives from wo and leaves along wi: the fibre scatters by S(wi, wo) (its
    // radiance form, over the wo side's cosine). The ribbon a light path met faces wo, so the
    // integrators' cosine |wi.z| for the next vertex is that ribbon's, where a fibre shows the
    // width facing wi (cos theta_i, as a camera path's ribbon does): rescaled to it.
    const float cz = std::fabs(wi.z);
    if (cz < 1e-6f) return RGB{0.f};
    return hair_f(l, wi, wo) * (safe_sqrt(1.f - wi.x * wi.x) / cz);
}

float hair_pdf(const Lobe& l, const Vec3& wo, const Vec3& wi) {
    const FibreAt at(l.hair, wo);
    return at.pdf(at.r.pdf(), wo, wi);
}

bool hair_sample(const Lobe& l, const Vec3& wo, float uc, Point2 u, BsdfSample& s, Transport mode) {
    const FibreAt at(l.hair, wo);
    const HairFiber& h = at.h;
    const Derived& d = at.d;
    const Refraction& r = at.r;
    const float sin_o = at.sin_o, cos_o = at.cos_o;
    const auto ap = r.pdf();
    // Pick p by the attenuations; uc is reused for the azimuth, rescaled within p's share.
    int p = 0;
    float below = 0.f;
    while (p < kPMax && uc >= below + ap[std::size_t(p)]) below += ap[std::size_t(p++)];
    if (ap[std::size_t(p)] <= 0.f) return false;
    uc = std::min((uc - below) / ap[std::size_t(p)], 0.99999994f);
    float sin_p, cos_p;
    d.tilt(p, sin_o, cos_o, sin_p, cos_p);
    const float v = d.v[p];
    const float cos_t = 1.f + v * std::log(std::max(u.x, 1e-5f) + (1.f - u.x) * std::exp(-2.f / v));
    const float sin_t = safe_sqrt(1.f - cos_t * cos_t);
    const float sin_i = -cos_t * sin_p + sin_t * std::cos(2.f * kPi * u.y) * cos_p;
    const float cos_i = safe_sqrt(1.f - sin_i * sin_i);
    const float dphi =
        p < kPMax ? deflection(p, safe_asin(h.h), r.gamma_t) + sample_trimmed_logistic(uc, d.s)
                  : 2.f * kPi * uc;
    const float phi_i = std::atan2(wo.z, wo.y) + dphi;
    s.wi = {sin_i, cos_i * std::cos(phi_i), cos_i * std::sin(phi_i)};
    s.pdf = at.pdf(ap, wo, s.wi);
    // Importance flows the other way: the adjoint (the fibre is not reciprocal).
    s.f = mode == Transport::Importance ? hair_adjoint_f(l, wo, s.wi) : at.f(wo, s.wi) * l.color;
    // The side it went to, as the integrators read a sample (a reflection stays on wo's side
    // of the surface, a transmission crosses it).
    s.flags = kGlossy | (s.wi.z * wo.z > 0.f ? kReflection : kTransmission);
    s.eta = 1.f;
    return s.pdf > 0.f;
}

RGB hair_sigma_a_from_melanin(float eumelanin, float pheomelanin) {
    return RGB{0.419f, 0.697f, 1.37f} * eumelanin + RGB{0.187f, 0.4f, 1.05f} * pheomelanin;
}

RGB hair_sigma_a_from_reflectance(const RGB& c, float bn) {
    const float denom = 5.969f - 0.215f * bn + 2.532f * bn * bn - 10.73f * bn * bn * bn +
                        5.574f * std::pow(bn, 4.f) + 0.245f * std::pow(bn, 5.f);
    return per_channel(c, [&](float x) {
        const float l = std::log(std::clamp(x, 1e-4f, 0.9999f)) / denom;
        return l * l;
    });
}

}  // namespace foton
