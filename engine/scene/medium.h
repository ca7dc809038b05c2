#pragma once
// Participating media (the photon-mapping thesis' future work; pbrt-v4's media): what fills the
// space between surfaces, and the boundaries that say which medium a ray is in.
//
// A medium absorbs (sigma_a), scatters (sigma_s) by the Henyey-Greenstein phase function of
// asymmetry g, and emits radiance Le where it absorbs (the emission term sigma_a Le of the
// radiative transfer equation, as pbrt-v4 writes it). Coefficients are per unit of scene length,
// RGB (no spectral sampling: foton renders in RGB throughout).
//
// Which medium a ray travels in is tracked, not looked up: the camera sits in one (or none), and
// a ray changes medium only where it crosses a surface whose object has a medium interface
// (inside != outside). Other surfaces leave the ray's medium as it was (pbrt-v4's rule), so a
// fog that fills a room needs one boundary, not one per wall.
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "blackbody_table.h"
#include "density_grid.h"
#include "engine/core/math.h"
#include "engine/core/rgb.h"
#include "engine/core/sampler.h"
#include "sampled_grid.h"

namespace foton {

inline constexpr int32_t kNoMedium = -1;  // vacuum

// exp(-sigma_t d) per channel: the exact transmittance of extinction sigma_t over d. A channel
// that does not extinguish is 1 even over an infinite d (not exp(-0 inf), NaN).
inline RGB exp_transmittance(const RGB& sigma_t, float d) {
    auto channel = [d](float st) { return st > 0.f ? std::exp(-st * d) : 1.f; };
    return {channel(sigma_t.r), channel(sigma_t.g), channel(sigma_t.b)};
}

// Homogeneous: the coefficients everywhere. Grid: the coefficients times a density grid's
// value (density_grid.h), inside its box only. RGBGrid: each coefficient its own RGB grid
// (sampled_grid.h), pbrt-v4's rgbgrid.
enum class MediumKind { Homogeneous, Grid, RGBGrid };

// A varying medium's coefficients at one point.
struct MediumPoint {
    RGB sigma_a, sigma_s;
};

struct Medium {
    std::string name;
    MediumKind kind = MediumKind::Homogeneous;
    RGB sigma_a{0.f}, sigma_s{0.f};
    RGB Le{0.f};    // emitted radiance (scaled by sigma_a in the transfer equation)
    float g = 0.f;  // Henyey-Greenstein asymmetry, in (-1, 1)
    // Grid: the density. RGBGrid: the bound on its extinction (each sample's largest channel
    // of sigma_a + sigma_s, before `grid_scale`), whose majorant grid the trackers walk.
    std::shared_ptr<const DensityGrid> density;
    // Grid: a grid scaling Le (pbrt-v4's "Lescale" array; null: 1 everywhere).
    std::shared_ptr<const DensityGrid> le_scale;
    // RGBGrid: the coefficients' and emission's grids (a null coefficient grid is 1
    // everywhere, pbrt-v4's default; a null Le grid emits nothing), the coefficients times
    // grid_scale and Le times le_factor.
    std::shared_ptr<const RGBGrid> rgb_sigma_a, rgb_sigma_s, rgb_Le;
    float grid_scale = 1.f, le_factor = 1.f;
    // Grid: a temperature grid whose blackbody glow is Le (pbrt-v4's temperature grids): Le(p)
    // = le_factor x le_scale(p) (1 without it) x the table's colour at (temperature(p) -
    // offset) x scale, nothing below 100 K. Le is unused then.
    std::shared_ptr<const DensityGrid> temperature;
    std::shared_ptr<const BlackbodyTable> blackbody;
    float temperature_offset = 0.f, temperature_scale = 1.f;
    // Where it was defined, for messages about it.
    std::string file;
    int line = 0;

    RGB sigma_t() const { return sigma_a + sigma_s; }
    // The majorant: no channel's extinction exceeds it, so free flights sampled with it and
    // corrected by null collisions are exact (delta tracking; transport/common/medium_tracking.h).
    // A grid medium's is this times its majorant grid's cell value.
    float majorant() const {
        return kind == MediumKind::RGBGrid ? grid_scale : sigma_t().max_component();
    }
    bool homogeneous() const { return kind == MediumKind::Homogeneous; }
    bool emits() const {
        if (kind == MediumKind::RGBGrid) return rgb_Le && le_factor > 0.f && grid_scale > 0.f;
        if (temperature) return le_factor > 0.f && !sigma_a.is_black();
        return !Le.is_black() && !sigma_a.is_black();
    }
    // A grid medium's coefficients at p (either grid kind).
    MediumPoint at(const Vec3& p) const;
    // A grid medium's emitted radiance Le at p (it glows sigma_a Le there); only an emitting
    // medium's trackers ask, so transmittance estimates never pay for it.
    RGB emission_at(const Vec3& p) const;
    // The exact transmittance of a homogeneous medium over d.
    RGB transmittance(float d) const { return exp_transmittance(sigma_t(), d); }
};

// The media on the two sides of an object's surface: inside is the side its geometric normal
// points away from. Equal sides (the default, both vacuum) are no boundary at all: a ray keeps
// its medium through the surface.
struct MediumInterface {
    int32_t inside = kNoMedium, outside = kNoMedium;
    bool transition() const { return inside != outside; }
    // The medium a ray is in after leaving this surface along a direction on the side its
    // outward normal points to (`outward`) or not, having been in `current` before.
    int32_t after(bool outward, int32_t current) const {
        if (!transition()) return current;
        return outward ? outside : inside;
    }
};

// The Henyey-Greenstein phase function (pbrt's convention: wo and wi both point away from the
// scattering point, so forward scattering, g > 0, favours wi = -wo). Normalised over the
// sphere; it is its own sampling density.
inline float henyey_greenstein(float cos_theta, float g) {
    const float denom = 1.f + g * g + 2.f * g * cos_theta;
    return (1.f / (4.f * kPi)) * (1.f - g * g) / (denom * std::sqrt(std::max(denom, 1e-12f)));
}

// Samples wi for a given wo from u in [0, 1)^2, exactly by the density above (the inverted
// CDF in cos theta); returns the density at wi.
inline float sample_henyey_greenstein(const Vec3& wo, float g, Point2 u, Vec3& wi) {
    float cos_theta;
    if (std::fabs(g) < 1e-3f) {
        cos_theta = 1.f - 2.f * u.x;
    } else {
        const float sq = (1.f - g * g) / (1.f - g + 2.f * g * u.x);
        cos_theta = (1.f + g * g - sq * sq) / (2.f * g);
    }
    cos_theta = std::clamp(cos_theta, -1.f, 1.f);
    const float sin_theta = std::sqrt(std::max(0.f, 1.f - cos_theta * cos_theta));
    const float phi = 2.f * kPi * u.y;
    // Measured from -wo: forward scattering is cos_theta near 1 about the continuing direction.
    const Vec3 axis = -wo;
    Vec3 s, t;
    orthonormal_basis(axis, s, t);
    wi = s * (sin_theta * std::cos(phi)) + t * (sin_theta * std::sin(phi)) + axis * cos_theta;
    return henyey_greenstein(dot(wo, wi), g);
}

}  // namespace foton
