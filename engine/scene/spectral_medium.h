#pragma once
// A participating medium seen at a spectral path's three wavelengths (core/spectrum.h): the
// interface the free-flight and transmittance estimators read (transport/common/
// medium_tracking.h takes either), with every coefficient an unbounded spectrum of its RGB
// and the emission an illuminant one, as pbrt-v4's spectral media are. RGB grids are converted
// where they are looked up; their majorant is four times the RGB one (an unbounded spectrum
// stays within twice its largest channel, and sigma_a and sigma_s are bounded apart).
#include <memory>

#include "engine/core/spectrum.h"
#include "medium.h"

namespace foton {

class SpectralMedium {
  public:
    SpectralMedium(const Medium& m, const Wavelengths& w)
        : sigma_a(w.unbounded(m.sigma_a)),
          sigma_s(w.unbounded(m.sigma_s)),
          Le(w.illuminant(m.Le)),
          g(m.g),
          density(m.density),
          base_(m),
          w_(w) {}
    RGB sigma_a, sigma_s, Le;
    float g;
    const std::shared_ptr<const DensityGrid>& density;

    RGB sigma_t() const { return sigma_a + sigma_s; }
    float majorant() const {
        return base_.kind == MediumKind::RGBGrid ? 4.f * base_.grid_scale
                                                 : sigma_t().max_component();
    }
    bool homogeneous() const { return base_.homogeneous(); }
    bool emits() const { return base_.emits(); }
    MediumPoint at(const Vec3& p) const {
        if (base_.kind == MediumKind::RGBGrid) {
            const MediumPoint c = base_.at(p);
            return {w_.unbounded(c.sigma_a), w_.unbounded(c.sigma_s)};
        }
        const float rho = density->lookup(p);
        return {sigma_a * rho, sigma_s * rho};
    }
    RGB emission_at(const Vec3& p) const { return w_.illuminant(base_.emission_at(p)); }
    RGB transmittance(float d) const { return exp_transmittance(sigma_t(), d); }

  private:
    const Medium& base_;
    const Wavelengths& w_;
};

}  // namespace foton
