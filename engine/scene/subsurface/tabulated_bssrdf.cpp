#include "tabulated_bssrdf.h"

#include <algorithm>
#include <cmath>

#include "engine/core/catmull_rom.h"

namespace foton {

namespace {

// The probability of each probe axis: the frame's s, t and n.
constexpr float kAxisProb[3] = {0.25f, 0.25f, 0.5f};

}  // namespace

TabulatedBssrdf::TabulatedBssrdf(const BssrdfTable& table, const Vec3& po, const Vec3& ns,
                                 const RGB& sigma_a, const RGB& sigma_s)
    : table_(table), po_(po), frame_(ns) {
    const float sa[3] = {sigma_a.r, sigma_a.g, sigma_a.b},
                ss[3] = {sigma_s.r, sigma_s.g, sigma_s.b};
    for (int c = 0; c < 3; ++c) {
        sigma_t_[c] = sa[c] + ss[c];
        rho_[c] = sigma_t_[c] > 0.f ? ss[c] / sigma_t_[c] : 0.f;
    }
}

float TabulatedBssrdf::profile(int c, float r, float* rho_eff) const {
    const float r_optical = r * sigma_t_[c];
    int ro = 0, co = 0;
    float wr[4], wc[4];
    if (!catmull_rom_weights(table_.rho, rho_[c], ro, wr) ||
        !catmull_rom_weights(table_.radius, r_optical, co, wc))
        return 0.f;
    float s = 0.f, eff = 0.f;
    for (int j = 0; j < 4; ++j) {
        if (wr[j] == 0.f) continue;
        eff += wr[j] * table_.rho_eff[std::size_t(ro + j)];
        for (int k = 0; k < 4; ++k)
            if (wc[k] != 0.f)
                s += wr[j] * wc[k] * table_.profile_at(std::size_t(ro + j), std::size_t(co + k));
    }
    if (rho_eff) *rho_eff = eff;
    // The table holds 2 pi r times the exitance (in optical units: times sigma_t^2 per area).
    if (r_optical != 0.f) s /= 2.f * kPi * r_optical;
    return s * sigma_t_[c] * sigma_t_[c];
}

RGB TabulatedBssrdf::sr(float r) const {
    return {std::max(0.f, profile(0, r, nullptr)), std::max(0.f, profile(1, r, nullptr)),
            std::max(0.f, profile(2, r, nullptr))};
}

float TabulatedBssrdf::pdf_sr(int c, float r) const {
    float rho_eff = 0.f;
    const float s = profile(c, r, &rho_eff);
    return rho_eff > 0.f ? std::max(0.f, s / rho_eff) : 0.f;
}

float TabulatedBssrdf::sample_sr(int c, float u) const {
    if (!(sigma_t_[c] > 0.f)) return -1.f;
    return sample_catmull_rom_2d(table_.rho, table_.radius, table_.profile, table_.profile_cdf,
                                 rho_[c], u) /
           sigma_t_[c];
}

bool TabulatedBssrdf::sample_probe(float u1, Point2 u2, BssrdfProbe& probe) const {
    // u1 picks the axis, and what is left of it within the axis' share the channel.
    int axis = 2;
    float rest = (u1 - 0.5f) / 0.5f;
    if (u1 < 0.25f) {
        axis = 0;
        rest = u1 / 0.25f;
    } else if (u1 < 0.5f) {
        axis = 1;
        rest = (u1 - 0.25f) / 0.25f;
    }
    const int c = std::min(2, int(rest * 3.f));
    const float r = sample_sr(c, u2.x);
    const float r_max = sample_sr(c, 0.999f);
    if (r < 0.f || !(r < r_max)) return false;
    const float phi = 2.f * kPi * u2.y;
    const Vec3 axes[3] = {frame_.s, frame_.t, frame_.n};
    const Vec3 along = axes[axis], a = axes[(axis + 1) % 3], b = axes[(axis + 2) % 3];
    const float half = std::sqrt(r_max * r_max - r * r);
    const Vec3 centre = po_ + (a * std::cos(phi) + b * std::sin(phi)) * r;
    probe = {centre - along * half, centre + along * half};
    return true;
}

float TabulatedBssrdf::pdf_sp(const Vec3& pi, const Vec3& ni) const {
    const Vec3 d = frame_.to_local(pi - po_), n = frame_.to_local(ni);
    // The distance from po in the plane across each axis.
    const float r_proj[3] = {std::sqrt(d.y * d.y + d.z * d.z), std::sqrt(d.z * d.z + d.x * d.x),
                             std::sqrt(d.x * d.x + d.y * d.y)};
    const float n_axis[3] = {n.x, n.y, n.z};
    float pdf = 0.f;
    for (int axis = 0; axis < 3; ++axis)
        for (int c = 0; c < 3; ++c)
            pdf += pdf_sr(c, r_proj[axis]) * std::fabs(n_axis[axis]) * kAxisProb[axis] / 3.f;
    return pdf;
}

}  // namespace foton
