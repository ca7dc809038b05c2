#pragma once
// Free flights through a participating medium (scene/medium.h), in the null-scattering form
// of Woodcock's delta tracking (Novák et al. 2014; Miller et al. 2019; pbrt-v4's volpath):
// tentative collisions are sampled with one scalar majorant sigma_maj >= every channel's
// sigma_t, and each is absorption, real scattering or a null collision. In RGB the choice is
// made in proportion to the coefficients weighted by the path's throughput (the channels'
// mean of beta sigma_x), and the throughput corrected per channel: every estimator stays
// unbiased for chromatic media (no hero wavelength, no spectral MIS), and the corrections
// keep the throughput's channel mean as it was, so they cannot grow without bound.
//
// Every estimator takes the medium as `M`: a scene/medium.h Medium (RGB) or a SpectralMedium
// (scene/spectral_medium.h: the same medium at a spectral path's three wavelengths).
//
// Transmittance along a shadow ray is either exact (a homogeneous medium's exp(-sigma_t d))
// or estimated by ratio tracking (Cline et al. 2005 / Novák et al. 2014): the product of
// sigma_n / sigma_maj over the tentative collisions, which is what a varying medium needs.
#include <cmath>
#include <cstdint>

#include "engine/core/math.h"
#include "engine/core/rgb.h"
#include "engine/scene/medium.h"
#include "kernels/grid_dda.h"
#include "kernels/majorant_march.h"

namespace foton {

struct FreeFlight {
    enum class Event : uint8_t { Scatter, Absorb, Pass };
    Event event = Event::Pass;
    float t = 0.f;     // where it scattered (Scatter)
    RGB weight{1.f};   // multiplies the path's throughput (Scatter, Pass)
    RGB emitted{0.f};  // the medium's emission gathered on the way, per unit throughput
    uint32_t collisions = 0;
};

// More tentative collisions than this in one flight end it as absorbed: only a majorant far
// above the medium's extinction gets there (a bound on time, not a bias in any scene we ship).
inline constexpr uint32_t kMaxCollisions = 1u << 20;

inline float channel_mean(const RGB& c) {
    return (c.r + c.g + c.b) * (1.f / 3.f);
}

// A tentative collision at t with majorant maj, where the medium's coefficients are sa and ss
// (sigma_n = maj - sa - ss per channel): absorption, real scattering or a null collision,
// chosen in proportion to the coefficients weighted by the throughput beta f.weight, the
// weight corrected by the choice's probability. Draws one number from u() unless the
// throughput is black. True when the flight goes on (a null collision).
template <class Uniform>
bool choose_collision(FreeFlight& f, const RGB& beta, const RGB& sa, const RGB& ss, float maj,
                      float t, Uniform&& u) {
    const RGB sn{maj - sa.r - ss.r, maj - sa.g - ss.g, maj - sa.b - ss.b};
    const RGB b = beta * f.weight;
    const float pa = channel_mean(b * sa), ps = channel_mean(b * ss),
                pn = std::max(0.f, channel_mean(b * sn));
    const float total = pa + ps + pn;
    if (!(total > 0.f)) {
        f.event = FreeFlight::Event::Absorb;
        return false;
    }
    const float x = u() * total;
    if (x < pa) {
        f.event = FreeFlight::Event::Absorb;
        f.weight = RGB{0.f};
        return false;
    }
    if (x < pa + ps) {
        f.event = FreeFlight::Event::Scatter;
        f.t = t;
        f.weight *= ss * (total / (ps * maj));
        return false;
    }
    f.weight *= sn * (total / (pn * maj));
    if (f.weight.is_black()) {
        f.event = FreeFlight::Event::Absorb;
        return false;
    }
    return true;
}

// One flight through medium m from t = 0 to t_end (kInfinity: nothing ahead) of a path with
// throughput `beta`, drawing uniform numbers in [0, 1) from u(). Pass: it reached t_end,
// weighted by the null collisions' corrections (exactly 1 when sigma_t is grey and equals the
// majorant).
template <class M, class Uniform>
FreeFlight delta_track(const M& m, float t_end, const RGB& beta, Uniform&& u) {
    FreeFlight f;
    const float maj = m.majorant();
    if (!(maj > 0.f)) return f;
    const bool emits = m.emits();
    float t = 0.f;
    for (;;) {
        t -= std::log1p(-u()) / maj;
        if (!(t < t_end)) return f;  // reached the end with the weight so far
        if (++f.collisions > kMaxCollisions) {
            f.event = FreeFlight::Event::Absorb;
            return f;
        }
        // The emission term sigma_a Le of every collision, then the collision's kind.
        if (emits) f.emitted += f.weight * m.sigma_a * m.Le * (1.f / maj);
        if (!choose_collision(f, beta, m.sigma_a, m.sigma_s, maj, t, u)) return f;
    }
}

// A homogeneous medium's flight sampled analytically. Only scattering is sampled: a channel c
// is chosen in proportion to the throughput `beta` (uniformly when it is black), the distance
// from sigma_s[c] exp(-sigma_s[c] t), and every channel weighted by the mixture of the three
// channels' densities (one-sample MIS over the channels with the balance heuristic, as RGB
// renderers sample chromatic media). Absorption is a weight, exp(-sigma_a t) within the
// transmittance: a flight scatters (weight T(t) sigma_s / pdf(t)) or passes (T(t_end) /
// P(pass)), and a purely absorbing medium passes every flight with exactly its transmittance.
// The emission along the segment is its exact integral, sigma_a Le (1 - T(t_end)) / sigma_t.
// Two numbers a flight.
template <class M, class Uniform>
FreeFlight sample_homogeneous(const M& m, float t_end, const RGB& beta, Uniform&& u) {
    FreeFlight f;
    const RGB st = m.sigma_t();
    if (m.emits()) {
        const RGB tr = m.transmittance(t_end);
        auto part = [](float sa, float le, float s, float t) {
            return s > 0.f ? sa * le * (1.f - t) / s : 0.f;
        };
        f.emitted = {part(m.sigma_a.r, m.Le.r, st.r, tr.r), part(m.sigma_a.g, m.Le.g, st.g, tr.g),
                     part(m.sigma_a.b, m.Le.b, st.b, tr.b)};
    }
    const float s[3] = {m.sigma_s.r, m.sigma_s.g, m.sigma_s.b};
    const float bsum = beta.r + beta.g + beta.b;
    float q[3] = {1.f / 3.f, 1.f / 3.f, 1.f / 3.f};
    if (bsum > 0.f) {
        q[0] = beta.r / bsum;
        q[1] = beta.g / bsum;
        q[2] = beta.b / bsum;
    }
    const float uc = u(), ut = u();
    const int c = uc < q[0] ? 0 : uc < q[0] + q[1] ? 1 : 2;
    const float t = s[c] > 0.f ? -std::log1p(-ut) / s[c] : kInfinity;
    if (t < t_end) {
        const float pdf = q[0] * s[0] * std::exp(-s[0] * t) + q[1] * s[1] * std::exp(-s[1] * t) +
                          q[2] * s[2] * std::exp(-s[2] * t);
        f.event = FreeFlight::Event::Scatter;
        f.t = t;
        f.collisions = 1;
        f.weight = pdf > 0.f ? m.transmittance(t) * m.sigma_s * (1.f / pdf) : RGB{0.f};
        return f;
    }
    // Passing: the probability that the chosen channel's flight outlasts the segment.
    const float p = q[0] * std::exp(-s[0] * t_end) + q[1] * std::exp(-s[1] * t_end) +
                    q[2] * std::exp(-s[2] * t_end);
    f.weight = p > 0.f ? m.transmittance(t_end) * (1.f / p) : RGB{0.f};
    if (f.weight.is_black()) f.event = FreeFlight::Event::Absorb;
    return f;
}

// The majorant grid of grid medium m as the march kernel reads it (kernels/majorant_march.h):
// the density bounds times the medium's largest channel's extinction (an RGB grid's: its
// extinction bounds times its scale).
template <class M>
kern::MajorantGrid majorant_view(const M& m) {
    const kern::GridFrame& f = m.density->majorant_frame();
    kern::MajorantGrid g;
    for (int a = 0; a < 3; ++a) {
        g.lo[a] = f.lo[a];
        g.cell[a] = f.cell[a];
        g.inv_cell[a] = f.inv_cell[a];
        g.res[a] = f.res[a];
    }
    g.majorant = m.density->majorant_data();
    g.scale = m.majorant();
    return g;
}

// The next tentative collision along o + t d after t, the optical depth -ln(1 - u) spent
// through the majorant grid (the march kernel's scalar twin, one flight): true with its
// point t and majorant, false when none comes before t_end.
template <class Uniform>
bool next_tentative_collision(const kern::MajorantGrid& g, const Vec3& o, const Vec3& d,
                              float t_end, Uniform&& u, float& t, float& maj) {
    const float tau = -std::log1p(-u());
    uint8_t hit = 0;
    const kern::MarchFlights f{&o.x, &o.y, &o.z, &d.x, &d.y, &d.z, &t_end, &tau, &t, &maj, &hit};
    kern::march_majorant_scalar(g, f, 1);
    return hit != 0;
}

// Delta tracking through grid medium m along o + t d: as delta_track, the tentative
// collisions drawn through the majorant grid (one optical depth at a time, march kernel), the
// coefficients and emission at a collision those of the grids there.
template <class M, class Uniform>
FreeFlight delta_track_grid(const M& m, const Vec3& o, const Vec3& d, float t_end, const RGB& beta,
                            Uniform&& u) {
    FreeFlight f;
    const kern::MajorantGrid g = majorant_view(m);
    const bool emits = m.emits();
    float t = 0.f, maj = 0.f;
    while (next_tentative_collision(g, o, d, t_end, u, t, maj)) {
        if (++f.collisions > kMaxCollisions) {
            f.event = FreeFlight::Event::Absorb;
            return f;
        }
        const Vec3 p = o + d * t;
        const MediumPoint c = m.at(p);
        if (emits) f.emitted += f.weight * c.sigma_a * m.emission_at(p) * (1.f / maj);
        if (!choose_collision(f, beta, c.sigma_a, c.sigma_s, maj, t, u)) return f;
    }
    return f;
}

// What a tentative collision with majorant maj leaves of the transmittance, per channel:
// sigma_n / maj at a point whose coefficients are c (ratio tracking's factor).
inline RGB null_fraction(const MediumPoint& c, float maj) {
    return {1.f - (c.sigma_a.r + c.sigma_s.r) / maj, 1.f - (c.sigma_a.g + c.sigma_s.g) / maj,
            1.f - (c.sigma_a.b + c.sigma_s.b) / maj};
}

// Ratio tracking's transmittance through grid medium m along o + t d over [0, t_end).
// on_step(t, product so far) follows every tentative collision: the running product is an
// unbiased estimate of the transmittance up to t, which the beam estimate reads.
struct NoRatioStep {
    void operator()(float, const RGB&) const {}
};
template <class M, class Uniform, class OnStep = NoRatioStep>
RGB ratio_track_grid(const M& m, const Vec3& o, const Vec3& d, float t_end, Uniform&& u,
                     OnStep&& on_step = {}) {
    RGB tr{1.f};
    const kern::MajorantGrid g = majorant_view(m);
    float t = 0.f, maj = 0.f;
    for (uint32_t k = 0; next_tentative_collision(g, o, d, t_end, u, t, maj); ++k) {
        tr *= null_fraction(m.at(o + d * t), maj);
        on_step(t, tr);
        if (tr.is_black() || k > kMaxCollisions) return RGB{0.f};
    }
    return tr;
}

// How camera paths sample their flights through a homogeneous medium: analytically (the
// default) or by delta tracking, the estimator varying media need, kept for homogeneous ones
// as a baseline to measure against. Grid media always take delta tracking.
enum class FreeFlightSampling : uint8_t { Analytic, Delta };

template <class M, class Uniform>
FreeFlight free_flight(const M& m, const Vec3& o, const Vec3& d, float t_end, const RGB& beta,
                       FreeFlightSampling how, Uniform&& u) {
    if (!m.homogeneous()) return delta_track_grid(m, o, d, t_end, beta, u);
    if (how == FreeFlightSampling::Delta) return delta_track(m, t_end, beta, u);
    return sample_homogeneous(m, t_end, beta, u);
}

// Ratio tracking's estimate of the transmittance over [0, d) (d finite).
template <class M, class Uniform>
RGB ratio_track(const M& m, float d, Uniform&& u) {
    const float maj = m.majorant();
    RGB tr{1.f};
    if (!(maj > 0.f)) return tr;
    const RGB ratio{1.f - (m.sigma_a.r + m.sigma_s.r) / maj,
                    1.f - (m.sigma_a.g + m.sigma_s.g) / maj,
                    1.f - (m.sigma_a.b + m.sigma_s.b) / maj};
    float t = 0.f;
    for (uint32_t k = 0; k < kMaxCollisions; ++k) {
        t -= std::log1p(-u()) / maj;
        if (!(t < d)) return tr;
        tr *= ratio;
        if (tr.is_black()) return tr;
    }
    return RGB{0.f};
}

// How shadow rays weigh a medium they cross.
enum class TransmittanceEstimator : uint8_t { Exact, Ratio };

// The transmittance along o + t dir over [0, d): grid media always by ratio tracking.
template <class M, class Uniform>
RGB transmittance(const M& m, const Vec3& o, const Vec3& dir, float d, TransmittanceEstimator e,
                  Uniform&& u) {
    if (!m.homogeneous()) return ratio_track_grid(m, o, dir, d, u);
    if (e == TransmittanceEstimator::Ratio) return ratio_track(m, d, u);
    return m.transmittance(d);  // homogeneous: exp(-sigma_t d), exactly
}

}  // namespace foton
