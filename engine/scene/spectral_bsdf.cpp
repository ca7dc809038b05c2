// Bsdf::to_wavelengths: a BSDF's RGB parameters as spectra at a path's wavelengths.
#include "bsdf.h"
#include "engine/core/spectrum.h"

namespace foton {

void Bsdf::to_wavelengths(const Wavelengths& w) {
    for (int i = 0; i < n_; ++i) {
        Lobe& l = lobes_[std::size_t(i)];
        l.color = w.reflectance(l.color);
        l.transmit = w.reflectance(l.transmit);
        if (l.fresnel.kind == FresnelKind::Conductor) {
            l.fresnel.eta = w.unbounded(l.fresnel.eta);
            l.fresnel.k = w.unbounded(l.fresnel.k);
        }
        l.fresnel.f0 = w.reflectance(l.fresnel.f0);
        l.coat.albedo = w.reflectance(l.coat.albedo);
        l.hair.sigma_a = w.unbounded(l.hair.sigma_a);
        if (l.type == LobeType::Measured)
            for (int k = 0; k < 3; ++k) l.lambda[k] = w.lambda[k];
    }
}

}  // namespace foton
