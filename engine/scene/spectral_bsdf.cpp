// Bsdf::to_wavelengths: a BSDF's RGB parameters as spectra at a path's wavelengths.
#include <algorithm>
#include <cmath>

#include "bsdf.h"
#include "engine/core/spectrum.h"

namespace foton {

void Bsdf::to_wavelengths(const Wavelengths& w) {
    for (int i = 0; i < n_; ++i) {
        Lobe& l = lobes_[std::size_t(i)];
        l.color = w.reflectance(l.color);
        l.transmit = w.reflectance(l.transmit);
        if (l.fresnel.kind == FresnelKind::Conductor) {
            if (l.fresnel.eta == RGB{1.f}) {
                // A conductor given by its normal reflectance r (metals.h: eta 1, k = 2
                // sqrt(r / (1 - r))): r upsampled as a reflectance and k made from it at each
                // wavelength, as pbrt-v4 does, rather than k upsampled.
                auto r_of = [](float k) { return k * k / (4.f + k * k); };
                const RGB r =
                    w.reflectance({r_of(l.fresnel.k.r), r_of(l.fresnel.k.g), r_of(l.fresnel.k.b)});
                auto k_of = [](float v) {
                    v = std::clamp(v, 0.f, 0.9999f);
                    return 2.f * std::sqrt(v / (1.f - v));
                };
                l.fresnel.k = {k_of(r.r), k_of(r.g), k_of(r.b)};
            } else {
                l.fresnel.eta = w.unbounded(l.fresnel.eta);
                l.fresnel.k = w.unbounded(l.fresnel.k);
            }
        }
        l.fresnel.f0 = w.reflectance(l.fresnel.f0);
        l.coat.albedo = w.reflectance(l.coat.albedo);
        l.hair.sigma_a = w.unbounded(l.hair.sigma_a);
        if (l.type == LobeType::Measured)
            for (int k = 0; k < 3; ++k) l.lambda[k] = w.lambda[k];
        if (l.dispersion.disperses()) l.fresnel.ior = l.dispersion.ior(w.lambda[0]);
    }
}

}  // namespace foton
