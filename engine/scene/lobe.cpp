// The lobes' constructors, their flags and the Fresnel terms they carry (bsdf.h); what a
// lobe does with directions is bsdf.cpp's (and rough_dielectric.cpp's).
#include <algorithm>

#include "bsdf.h"
#include "engine/core/optics.h"
#include "measured_brdf.h"
#include "subsurface/bssrdf_table.h"

namespace foton {

RGB Fresnel::eval(float cos_i) const {
    switch (kind) {
        case FresnelKind::None:
            return RGB{1.f};
        case FresnelKind::Dielectric:
            return RGB{fresnel_dielectric(cos_i, 1.f, ior)};
        case FresnelKind::Conductor:
            return {fresnel_conductor(cos_i, eta.r, k.r), fresnel_conductor(cos_i, eta.g, k.g),
                    fresnel_conductor(cos_i, eta.b, k.b)};
        case FresnelKind::Schlick: {
            const float m = 1.f - std::clamp(cos_i, 0.f, 1.f);
            const float m2 = m * m;
            return f0 + (RGB{1.f} - f0) * (m2 * m2 * m);
        }
    }
    return RGB{1.f};
}

Fresnel Fresnel::schlick(const RGB& f0) {
    Fresnel f;
    f.kind = FresnelKind::Schlick;
    f.f0 = f0;
    return f;
}

namespace {

bool distribution_anisotropic(const MicrofacetDistribution& d) {
    switch (d.kind) {
        case MicrofacetKind::TrowbridgeReitz:
            return d.alpha != d.alpha_y;
        case MicrofacetKind::AshikhminShirley:
            return d.nu != d.nv;
        default:
            return false;
    }
}

}  // namespace

bool Lobe::anisotropic() const {
    const Lobe& l = *this;
    switch (l.type) {
        case LobeType::Microfacet:
        case LobeType::RoughDielectric:
            return distribution_anisotropic(l.dist);
        case LobeType::Hair:
            return true;  // its frame's x must run along the fibre
        case LobeType::Measured:
            return !l.measured->isotropic;  // its data are by azimuth
        case LobeType::Coated:
            return (!l.coat.coat_smooth && distribution_anisotropic(l.coat.coat)) ||
                   (l.coat.base == CoatBase::Conductor && !l.coat.base_smooth &&
                    distribution_anisotropic(l.dist));
        default:
            return false;
    }
}

uint8_t Lobe::flags() const {
    switch (type) {
        case LobeType::Lambert:
        case LobeType::OrenNayar:
        case LobeType::SubsurfaceExit:
            return kDiffuse | kReflection;
        case LobeType::Phong:
        case LobeType::Microfacet:
        case LobeType::Measured:
            return kGlossy | kReflection;
        case LobeType::Mirror:
            return kSpecular | kReflection;
        case LobeType::Dielectric:
        case LobeType::ThinDielectric:
            return kSpecular | kReflection | kTransmission;
        case LobeType::RoughDielectric:
        case LobeType::Hair:  // a fibre scatters all round
            return kGlossy | kReflection | kTransmission;
        case LobeType::LambertTransmission:
            return kDiffuse | kTransmission;
        case LobeType::Coated:
            // Glossy, not pbrt's diffuse + specular: foton's integrators split a BSDF by its
            // lobes' flags (delta lobes traced, the others estimated), and the walk mixes
            // both. Its delta samples (the smooth coat's mirror reflection) say so themselves.
            return coat_is_delta() ? kSpecular | kReflection : kGlossy | kReflection;
    }
    return 0;
}

Lobe Lobe::measured_brdf(const MeasuredBrdf* b) {
    Lobe l;
    l.type = LobeType::Measured;
    l.color = RGB{1.f};
    l.measured = b;
    return l;
}

Lobe Lobe::hair_fiber(const HairFiber& h) {
    Lobe l;
    l.type = LobeType::Hair;
    l.color = RGB{1.f};
    l.hair = h;
    return l;
}

Lobe Lobe::lambert(const RGB& r) {
    Lobe l;
    l.type = LobeType::Lambert;
    l.color = r;
    return l;
}

Lobe Lobe::oren_nayar(const RGB& r, float sigma) {
    Lobe l;
    l.type = LobeType::OrenNayar;
    l.color = r;
    const float s2 = sigma * sigma;
    l.on_a = 1.f - s2 / (2.f * (s2 + 0.33f));
    l.on_b = 0.45f * s2 / (s2 + 0.09f);
    return l;
}

Lobe Lobe::phong(const RGB& ks, float exponent) {
    Lobe l;
    l.type = LobeType::Phong;
    l.color = ks;
    l.exponent = exponent;
    return l;
}

Lobe Lobe::mirror(const RGB& r, const Fresnel& f) {
    Lobe l;
    l.type = LobeType::Mirror;
    l.color = r;
    l.fresnel = f;
    return l;
}

Lobe Lobe::dielectric(float ior, const RGB& reflect, const RGB& transmit) {
    Lobe l;
    l.type = LobeType::Dielectric;
    l.color = reflect;
    l.transmit = transmit;
    l.fresnel.kind = FresnelKind::Dielectric;
    l.fresnel.ior = ior;
    return l;
}

Lobe Lobe::thin_dielectric(float ior, const RGB& reflect, const RGB& transmit) {
    Lobe l = dielectric(ior, reflect, transmit);
    l.type = LobeType::ThinDielectric;
    return l;
}

Lobe Lobe::microfacet(const RGB& tint, const MicrofacetDistribution& d, const Fresnel& f) {
    Lobe l;
    l.type = LobeType::Microfacet;
    l.color = tint;
    l.dist = d;
    l.fresnel = f;
    return l;
}

Lobe Lobe::lambert_transmission(const RGB& t) {
    Lobe l;
    l.type = LobeType::LambertTransmission;
    l.color = t;
    return l;
}

Lobe Lobe::subsurface_exit(float eta) {
    Lobe l;
    l.type = LobeType::SubsurfaceExit;
    l.fresnel.kind = FresnelKind::Dielectric;
    l.fresnel.ior = eta;
    // 1 / c: c = 1 - 2 int_0^1 F(mu) mu dmu is the share of diffuse light the boundary lets in.
    l.color = RGB{float(1.0 / (1.0 - 2.0 * fresnel_moment(1, 1.0, double(eta))))};
    return l;
}

Lobe Lobe::rough_dielectric(float ior, const MicrofacetDistribution& d, const RGB& reflect,
                            const RGB& transmit) {
    Lobe l = dielectric(ior, reflect, transmit);
    l.type = LobeType::RoughDielectric;
    l.dist = d;
    return l;
}

Lobe Lobe::coated_diffuse(const RGB& r, const CoatLayer& c) {
    Lobe l;
    l.type = LobeType::Coated;
    l.color = r;
    l.coat = c;
    l.coat.base = CoatBase::Diffuse;
    return l;
}

Lobe Lobe::coated_conductor(const Fresnel& f, bool smooth, const MicrofacetDistribution& d,
                            const CoatLayer& c) {
    Lobe l;
    l.type = LobeType::Coated;
    l.color = RGB{1.f};
    l.fresnel = f;
    l.dist = d;
    l.coat = c;
    l.coat.base = CoatBase::Conductor;
    l.coat.base_smooth = smooth;
    return l;
}

}  // namespace foton
