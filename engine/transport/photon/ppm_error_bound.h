#pragma once
// The error bound of progressive photon mapping and the stopping rule built on it: the
// photon-mapping thesis' 8.1.1 asks for "a criterion that stops the rendering once the wanted
// accuracy is reached", which needs the variance of the estimate near a point. Our form of
// Hachisuka, Jarosz and Jensen's progressive error estimation (2010):
//
// After n passes a pixel's value is the mean of its passes' own estimates
//     Y_j = d_j + Phi_j / (pi R_j^2)
// (d_j the pass's direct light, Phi_j the flux its photons brought within the radius R_j):
// PPM's update tau' = (tau + Phi) R'^2 / R^2 makes tau_n / R_n^2 = sum_j Phi_j / R_j^2
// exactly. Each pass also estimates its own leading bias from the photons within 2 R_j: a
// disc of radius R blurs a density by R^2 lap(L) / 8 + O(R^4) (the uniform disc's second
// moment, R^2 / 4 per axis), so
//     b_j = (Phi_wide_j / (4 pi R_j^2) - Phi_j / (pi R_j^2)) / 3
// has the expectation of the pass's bias to leading order (the wider disc, not a narrower one:
// its photons make b_j's noise 0.3 x the estimate's own instead of 2 x with R / sqrt 2, at the
// price of a larger O(R^4) term and 4 x the photons to visit). The bias-corrected X_j = Y_j - b_j
// then share one mean with different variances (the radius shrinks), and for independent
// passes sum_j (X_j - mean X)^2 n / (n - 1) estimates the sum of their variances without a
// model of how they fall. The bound, at confidence c, on |pixel - true value|:
//     |mean b| + t_{n-1, (1+c)/2} sqrt(sum Var / n^2),
// per channel (Student's t from Boost.Math). The scalar bound of a pixel is the luminance of
// its channel bounds, which bounds the error of its luminance.
//
// The rule: stop after a pass once the mean of the pixels' scalar bounds is at most
// `relative` times the image's mean luminance (and at least kMinPasses have run, so the
// variance estimate has a few degrees of freedom).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/core/rgb.h"
#include "engine/film/pixel_owners.h"

namespace foton {

class PpmErrorBound {
  public:
    static constexpr uint32_t kMinPasses = 8;

    PpmErrorBound(std::size_t pixels, float confidence);

    // Pass j's estimate of `pixel` (Y_j) and its bias estimate (b_j).
    void record(std::size_t pixel, const RGB& estimate, const RGB& bias);
    // The bound on each channel of `pixel`'s error after `passes` recorded passes (0 before
    // two passes: no spread is known yet; the stopping rule waits for kMinPasses).
    RGB bound(std::size_t pixel, uint32_t passes) const;
    // The same with t = t_factor(passes) given (a quantile costs microseconds: once per image).
    RGB bound(std::size_t pixel, uint32_t passes, double t) const;
    // The mean bias estimate the bound includes.
    RGB bias(std::size_t pixel, uint32_t passes) const;
    // Student's t quantile of the bound after `passes` passes.
    double t_factor(uint32_t passes) const;

    // Whether the render may stop after `passes`: the mean over the image of the pixels'
    // scalar bounds against `relative` times the image's mean luminance (`image` the pixel
    // values). Across MPI ranks each pixel's terms come from the rank that owns it and rank 0
    // sums them in pixel order (as one process would); `mean_bound` and `mean_value` get the
    // two means (on rank 0).
    bool converged(uint32_t passes, float relative, const std::vector<RGB>& image,
                   const Cluster& cluster, const PixelOwners& owner, double& mean_bound,
                   double& mean_value) const;

  private:
    struct Sums {
        double x[3] = {0, 0, 0};   // sum of X_j = Y_j - b_j
        double xx[3] = {0, 0, 0};  // sum of X_j^2
        double b[3] = {0, 0, 0};   // sum of b_j
    };
    std::vector<Sums> sums_;
    float confidence_;
};

}  // namespace foton
