#include "microfacet.h"

namespace foton {

const char* microfacet_name(MicrofacetKind k) {
    switch (k) {
        case MicrofacetKind::Blinn:
            return "blinn";
        case MicrofacetKind::Beckmann:
            return "beckmann";
        case MicrofacetKind::AshikhminShirley:
            return "ashikhmin_shirley";
    }
    return "?";
}

MicrofacetDistribution MicrofacetDistribution::blinn(float exponent) {
    MicrofacetDistribution d;
    d.kind = MicrofacetKind::Blinn;
    d.nu = d.nv = exponent;
    return d;
}

MicrofacetDistribution MicrofacetDistribution::beckmann(float alpha) {
    MicrofacetDistribution d;
    d.kind = MicrofacetKind::Beckmann;
    d.alpha = alpha;
    return d;
}

MicrofacetDistribution MicrofacetDistribution::ashikhmin_shirley(float nu, float nv) {
    MicrofacetDistribution d;
    d.kind = MicrofacetKind::AshikhminShirley;
    d.nu = nu;
    d.nv = nv;
    return d;
}

float MicrofacetDistribution::D(const Vec3& h) const {
    const float c = h.z;
    if (c <= 0.f) return 0.f;
    if (kind == MicrofacetKind::Beckmann) {
        const float c2 = c * c;
        const float tan2 = (1.f - c2) / c2;
        return std::exp(-tan2 / (alpha * alpha)) / (kPi * alpha * alpha * c2 * c2);
    }
    // cos^e(theta) with e = nu cos^2(phi) + nv sin^2(phi); Blinn is nu = nv. The marginal over
    // phi of cos^(e+1) sin integrates to 2 pi / sqrt((nu+2)(nv+2)), hence the normalisation.
    const float s2 = h.x * h.x + h.y * h.y;
    const float e = s2 > 0.f ? (nu * h.x * h.x + nv * h.y * h.y) / s2 : nu;
    return std::sqrt((nu + 2.f) * (nv + 2.f)) * (0.5f * kInvPi) * std::pow(c, e);
}

Vec3 MicrofacetDistribution::sample_h(Point2 u) const {
    float cos_t, phi;
    if (kind == MicrofacetKind::Beckmann) {
        const float tan2 = -alpha * alpha * std::log(1.f - u.x);
        cos_t = 1.f / std::sqrt(1.f + tan2);
        phi = 2.f * kPi * u.y;
    } else {
        // phi from the marginal 1 / ((nu+2) cos^2 + (nv+2) sin^2), inverted per quadrant;
        // then cos(theta) = u^(1 / (e(phi) + 2)).
        if (nu == nv) {
            phi = 2.f * kPi * u.y;
        } else {
            const float q = 4.f * u.y;
            const int quadrant = std::min(3, int(q));
            const float f = q - float(quadrant);
            float base = std::atan(std::sqrt((nu + 2.f) / (nv + 2.f)) * std::tan(0.5f * kPi * f));
            // The density is symmetric about both axes: mirror the first quadrant.
            if (quadrant == 1) base = kPi - base;
            if (quadrant == 3) base = 2.f * kPi - base;
            if (quadrant == 2) base = kPi + base;
            phi = base;
        }
        const float cp = std::cos(phi), sp = std::sin(phi);
        const float e = nu * cp * cp + nv * sp * sp;
        cos_t = std::pow(u.x, 1.f / (e + 2.f));
    }
    const float sin_t = std::sqrt(std::max(0.f, 1.f - cos_t * cos_t));
    return {sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t};
}

}  // namespace foton
