// Bsdf::regularized: pbrt-v4's path regularisation (its BxDF::Regularize), for the
// integrators' `regularize` setting.
#include <algorithm>

#include "bsdf.h"

namespace foton {

namespace {

// A roughness below 0.3 doubled, kept within [0.1, 0.3] (a specular one becomes 0.1):
// Trowbridge–Reitz's alphas, as pbrt-v4's, and Beckmann's slope alike; the thesis' Blinn and
// Ashikhmin–Shirley exponents stay.
void roughen(MicrofacetDistribution& d) {
    auto up = [](float a) { return a < 0.3f ? std::clamp(2.f * a, 0.1f, 0.3f) : a; };
    if (d.kind != MicrofacetKind::TrowbridgeReitz && d.kind != MicrofacetKind::Beckmann) return;
    d.alpha = up(d.alpha);
    d.alpha_y = up(d.alpha_y);
}

}  // namespace

Bsdf Bsdf::regularized() const {
    Bsdf out;
    const auto smooth = MicrofacetDistribution::trowbridge_reitz(0.f, 0.f);
    for (int i = 0; i < n_; ++i) {
        Lobe l = lobes_[std::size_t(i)];
        switch (l.type) {
            case LobeType::Mirror:
                l.type = LobeType::Microfacet;
                l.dist = smooth;
                roughen(l.dist);
                break;
            case LobeType::Dielectric:
                l.type = LobeType::RoughDielectric;
                l.dist = smooth;
                roughen(l.dist);
                break;
            case LobeType::Microfacet:
            case LobeType::RoughDielectric:
                roughen(l.dist);
                break;
            case LobeType::Coated:
                // Both interfaces of the layer, as pbrt-v4's LayeredBxDF does.
                roughen(l.coat.coat);
                l.coat.coat_smooth = false;
                if (l.coat.base == CoatBase::Conductor) {
                    if (l.coat.base_smooth) l.dist = smooth;
                    roughen(l.dist);
                    l.coat.base_smooth = false;
                }
                break;
            default:
                break;  // diffuse lobes, thin panes, fibres and measured data stay as they are
        }
        out.add(l);
    }
    return out;
}

}  // namespace foton
