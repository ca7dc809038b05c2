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
        case MicrofacetKind::TrowbridgeReitz:
            return "trowbridge_reitz";
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

MicrofacetDistribution MicrofacetDistribution::trowbridge_reitz(float alpha_x, float alpha_y) {
    MicrofacetDistribution d;
    d.kind = MicrofacetKind::TrowbridgeReitz;
    d.alpha = alpha_x;
    d.alpha_y = alpha_y;
    return d;
}

float MicrofacetDistribution::lambda(const Vec3& w) const {
    const float z2 = w.z * w.z;
    if (z2 == 0.f) return kInfinity;
    // alpha^2 tan^2(theta) along the direction's azimuth.
    const float ax = w.x * alpha, ay = w.y * alpha_y;
    const float a2t2 = (ax * ax + ay * ay) / z2;
    return 0.5f * (std::sqrt(1.f + a2t2) - 1.f);
}

Vec3 MicrofacetDistribution::sample_visible(const Vec3& wo, Point2 u) const {
    // Stretch wo into the configuration of roughness 1, where the visible normals are those
    // of a hemisphere seen from wh: a disc point, warped towards the visible half, lifted
    // onto the hemisphere and stretched back.
    const Vec3 wh = normalize(Vec3{alpha * wo.x, alpha_y * wo.y, wo.z});
    const float l2 = wh.x * wh.x + wh.y * wh.y;
    const Vec3 t1 = l2 > 0.f ? Vec3{-wh.y, wh.x, 0.f} * (1.f / std::sqrt(l2)) : Vec3{1.f, 0.f, 0.f};
    const Vec3 t2 = cross(wh, t1);
    const float r = std::sqrt(u.x), phi = 2.f * kPi * u.y;
    const float p1 = r * std::cos(phi);
    float p2 = r * std::sin(phi);
    const float s = 0.5f * (1.f + wh.z);
    p2 = (1.f - s) * std::sqrt(std::max(0.f, 1.f - p1 * p1)) + s * p2;
    const float pz = std::sqrt(std::max(0.f, 1.f - p1 * p1 - p2 * p2));
    const Vec3 nh = t1 * p1 + t2 * p2 + wh * pz;
    return normalize(Vec3{alpha * nh.x, alpha_y * nh.y, std::max(1e-6f, nh.z)});
}

float MicrofacetDistribution::D(const Vec3& h) const {
    const float c = h.z;
    if (c <= 0.f) return 0.f;
    if (kind == MicrofacetKind::TrowbridgeReitz) {
        // 1 / (pi ax ay cos^4 (1 + tan^2 (cos^2 phi / ax^2 + sin^2 phi / ay^2))^2), written
        // with the unit normal's components: no tangent that overflows near the horizon.
        const float x = h.x / alpha, y = h.y / alpha_y;
        const float s = c * c + x * x + y * y;
        return 1.f / (kPi * alpha * alpha_y * s * s);
    }
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
