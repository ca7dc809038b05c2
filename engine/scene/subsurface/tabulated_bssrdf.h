#pragma once
// A subsurface material's BSSRDF at one entry point po (pbrt-v4's TabulatedBSSRDF in RGB):
// separable, S = Sp(|pi - po|) Sw(wi), the spatial part the table's profile of the
// channel's albedo rho = sigma_s / sigma_t at optical radius r sigma_t, scaled by sigma_t^2.
//
// Exit points are found by probes: a channel (one of three) and an axis of the frame at po
// (the normal with probability 1/2, either tangent 1/4) are chosen, a radius r drawn from
// the channel's profile and an angle uniformly; the probe is the chord through the sphere
// of the profile's 99.9 % radius along the axis, at that offset. Where it meets the
// material's surface is an exit point. Its density per unit area, pdf_sp, sums every
// (axis, channel) way of reaching it (one-sample MIS, balance heuristic); the radiance
// weight of an exit point is Sp / (pdf_sp times the chance of picking it among the probe's
// hits).
#include "bssrdf_table.h"
#include "engine/core/math.h"
#include "engine/core/rgb.h"
#include "engine/core/warp.h"

namespace foton {

// The probe: the segment from p0 to p1 whose crossings of the material are the candidates.
struct BssrdfProbe {
    Vec3 p0, p1;
};

class TabulatedBssrdf {
  public:
    TabulatedBssrdf(const BssrdfTable& table, const Vec3& po, const Vec3& ns, const RGB& sigma_a,
                    const RGB& sigma_s);

    // Sr: the spatial profile at distance r, per channel (per unit area).
    RGB sr(float r) const;
    RGB sp(const Vec3& pi) const { return sr(length(pi - po_)); }
    // The probe for numbers u1 (axis and channel) and u2 (radius and angle); false when the
    // radius drawn lies beyond the profile's reach (the sample is lost, as in pbrt-v4).
    bool sample_probe(float u1, Point2 u2, BssrdfProbe& probe) const;
    // The density per unit area of exit point pi (surface normal ni) over every way a probe
    // could have reached it.
    float pdf_sp(const Vec3& pi, const Vec3& ni) const;

    // Channel c's radius for profile quantile u (negative: the channel does not scatter).
    float sample_sr(int c, float u) const;
    // Channel c's density of a point at distance r in the probe's disc (per unit area).
    float pdf_sr(int c, float r) const;

  private:
    // Channel c's profile at distance r per unit area (interpolated in albedo and optical
    // radius), and the effective albedo of the channel's albedo when `rho_eff` is given.
    float profile(int c, float r, float* rho_eff) const;

    const BssrdfTable& table_;
    Vec3 po_;
    warp::Frame frame_;
    float sigma_t_[3], rho_[3];
};

}  // namespace foton
