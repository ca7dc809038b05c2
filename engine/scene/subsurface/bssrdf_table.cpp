#include "bssrdf_table.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "engine/core/catmull_rom.h"
#include "engine/core/math.h"
#include "kernels/fresnel.h"

namespace foton {

namespace {

constexpr int kDepthSamples = 100;  // beam depths per evaluation, as pbrt-v4 takes
constexpr std::size_t kRhoSamples = 100, kRadiusSamples = 64;

// The depth of quantile u of an exponential distribution of rate a.
float exponential_quantile(float u, float a) {
    return -std::log(1.f - u) / a;
}

// Henyey-Greenstein in pbrt-v4's argument (the cosine between the directions both pointing
// away from the scattering point).
float henyey_greenstein_pbrt(float cos_theta, float g) {
    const float denom = 1.f + g * g + 2.f * g * cos_theta;
    return (1.f - g * g) / (4.f * kPi * denom * std::sqrt(std::max(denom, 0.f)));
}

}  // namespace

double fresnel_moment(int i, double eta_i, double eta_t) {
    // The midpoint rule on 4096 cosines: the integrand has a kink at the critical angle only.
    constexpr int n = 4096;
    double sum = 0.0;
    for (int k = 0; k < n; ++k) {
        const double mu = (k + 0.5) / n;
        sum += double(kern::fresnel_dielectric(float(mu), float(eta_i), float(eta_t))) *
               std::pow(mu, i);
    }
    return sum / n;
}

namespace {

// Photon beam diffusion's multiple-scattering term (the dipoles along the beam) at radius r,
// with the boundary's Fresnel moments (of eta -> 1: light inside meeting the boundary) given.
float multiple_with_moments(float sigma_s, float sigma_a, float g, float fm1, float fm2, float r) {
    // Reduced coefficients, Grosjean's diffusion coefficient and the transport coefficient.
    const float sps = sigma_s * (1.f - g), spt = sigma_a + sps, rhop = sps / spt;
    const float D = (2.f * sigma_a + sps) / (3.f * spt * spt);
    const float sigma_tr = std::sqrt(std::max(0.f, sigma_a / D));
    const float ze = -2.f * D * (1.f + 3.f * fm2) / (1.f - 2.f * fm1);
    const float c_phi = 0.25f * (1.f - 2.f * fm1), c_e = 0.5f * (1.f - 3.f * fm2);
    double sum = 0.0;
    for (int k = 0; k < kDepthSamples; ++k) {
        // A real source at depth zr along the beam, its mirror source above the boundary.
        const float zr = exponential_quantile((k + 0.5f) / kDepthSamples, spt);
        const float zv = -zr + 2.f * ze;
        const float dr = std::sqrt(r * r + zr * zr), dv = std::sqrt(r * r + zv * zv);
        const float er = std::exp(-sigma_tr * dr), ev = std::exp(-sigma_tr * dv);
        const float fluence = (er / dr - ev / dv) / (4.f * kPi * D);
        const float flux = (zr * (1.f + sigma_tr * dr) * er / (dr * dr * dr) -
                            zv * (1.f + sigma_tr * dv) * ev / (dv * dv * dv)) /
                           (4.f * kPi);
        // kappa: the beam's first scattering must lie beyond the surface it came through.
        const float kappa = 1.f - std::exp(-2.f * spt * (dr + zr));
        sum += double(kappa * rhop * rhop * (fluence * c_phi + flux * c_e));
    }
    return float(sum / kDepthSamples);
}

// Photon beam diffusion's single-scattering term at radius r for a beam entering a medium of
// these coefficients under a boundary of relative index eta (inside over outside).
float beam_diffusion_single(float sigma_s, float sigma_a, float g, float eta, float r) {
    const float sigma_t = sigma_a + sigma_s, rho = sigma_s / sigma_t;
    // Below this depth the path to the exit point would leave beyond the critical angle.
    const float t_crit = r * std::sqrt(std::max(0.f, eta * eta - 1.f));
    double sum = 0.0;
    for (int k = 0; k < kDepthSamples; ++k) {
        const float t = t_crit + exponential_quantile((k + 0.5f) / kDepthSamples, sigma_t);
        const float d = std::sqrt(r * r + t * t), cos_o = t / d;
        sum += double(rho * std::exp(-sigma_t * (d + t_crit)) / (d * d) *
                      henyey_greenstein_pbrt(cos_o, g) *
                      (1.f - kern::fresnel_dielectric(cos_o, eta, 1.f)) * cos_o);
    }
    return float(sum / kDepthSamples);
}

}  // namespace

BssrdfTable BssrdfTable::compute(float g, float eta) {
    BssrdfTable t;
    t.g = g;
    t.eta = eta;
    t.radius.resize(kRadiusSamples);
    t.radius[0] = 0.f;
    t.radius[1] = 2.5e-3f;
    for (std::size_t j = 2; j < kRadiusSamples; ++j) t.radius[j] = t.radius[j - 1] * 1.2f;
    // Albedos crowd towards 1, where the profiles change fastest.
    t.rho.resize(kRhoSamples);
    for (std::size_t i = 0; i < kRhoSamples; ++i)
        t.rho[i] =
            (1.f - std::exp(-8.f * float(i) / float(kRhoSamples - 1))) / (1.f - std::exp(-8.f));
    t.profile.assign(kRhoSamples * kRadiusSamples, 0.f);
    t.profile_cdf.assign(kRhoSamples * kRadiusSamples, 0.f);
    t.rho_eff.assign(kRhoSamples, 0.f);
    const float fm1 = float(fresnel_moment(1, eta, 1.0)), fm2 = float(fresnel_moment(2, eta, 1.0));
    tbb::parallel_for(std::size_t(0), kRhoSamples, [&](std::size_t i) {
        const float rho = t.rho[i];
        float* row = &t.profile[i * kRadiusSamples];
        for (std::size_t j = 0; j < kRadiusSamples; ++j) {
            const float r = t.radius[j];
            row[j] = 2.f * kPi * r *
                     (beam_diffusion_single(rho, 1.f - rho, g, eta, r) +
                      multiple_with_moments(rho, 1.f - rho, g, fm1, fm2, r));
        }
        t.rho_eff[i] = integrate_catmull_rom(
            t.radius, std::span<const float>(row, kRadiusSamples),
            std::span<float>(&t.profile_cdf[i * kRadiusSamples], kRadiusSamples));
    });
    return t;
}

float BssrdfTable::albedo_for(float rho_eff_target) const {
    return invert_catmull_rom(rho, rho_eff, rho_eff_target);
}

}  // namespace foton
