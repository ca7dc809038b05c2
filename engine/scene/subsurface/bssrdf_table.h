#pragma once
// The diffusion profiles of a subsurface material (pbrt-v4's tabulated BSSRDF, after Habel
// et al. 2013's photon beam diffusion): for a medium of unit extinction, albedo rho, phase
// asymmetry g, under a boundary of relative index eta, the radiant exitance at distance r
// from where a beam entered, single scattering plus the multiple-scattering dipoles summed
// along the refracted beam. Tabulated once per (g, eta) over 100 albedos and 64 radii (r
// geometric from 2.5e-3 by factors of 1.2, so to ~2.4e2 optical radii); a material scales
// r by its extinction (TabulatedBssrdf).
#include <vector>

namespace foton {

// The Fresnel moment int_0^1 F_r(mu) mu^i dmu of light crossing from index eta_i into eta_t
// (F_r: fresnel_dielectric; total internal reflection counts 1), integrated numerically.
double fresnel_moment(int i, double eta_i, double eta_t);

struct BssrdfTable {
    float g = 0.f, eta = 1.33f;
    std::vector<float> rho;     // the albedos of the rows
    std::vector<float> radius;  // optical radii of the columns
    // Row i: 2 pi r times the exitance at each radius (the profile's density in r, not
    // normalised); its running integral and its total, the effective albedo rho_eff.
    std::vector<float> profile, profile_cdf;
    std::vector<float> rho_eff;

    // The table of (g, eta) (a few hundred ms: rows in parallel).
    static BssrdfTable compute(float g, float eta);
    float profile_at(std::size_t row, std::size_t col) const {
        return profile[row * radius.size() + col];
    }
    // The single-scattering albedo whose effective albedo is `rho_eff_target` (the inversion
    // of rho_eff), for materials given by their diffuse reflectance.
    float albedo_for(float rho_eff_target) const;
};

}  // namespace foton
