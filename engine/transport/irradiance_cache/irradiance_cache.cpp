#include "irradiance_cache.h"

#include <algorithm>
#include <cmath>

namespace foton {

namespace {
// Records in front of the query point (the query lies behind the record's tangent plane by
// more than this fraction of R_i) are not used: Ward's test against interpolating into
// concave creases from the wrong side.
constexpr float kFrontTolerance = 0.05f;
// The minimum-distance radius ignores rays further than this from the normal (cos 60 deg).
constexpr float kMinimumRuleCos = 0.5f;
}  // namespace

float record_influence(const CacheParams& params, const IrradianceRecord& r) {
    if (params.weight == CacheWeight::Ward) return params.a * r.r;
    return std::clamp(2.f * r.r_harmonic, r.r_min, r.r_max) / params.kappa;
}

float CacheParams::normal_limit() const {
    return std::sqrt(1.f - std::cos(max_angle_deg * kPi / 180.f));
}

float record_weight(const CacheParams& params, const IrradianceRecord& r, const Vec3& p,
                    const Vec3& n) {
    return record_weight(params, params.normal_limit(), r, p, n);
}

float record_weight(const CacheParams& params, float normal_limit, const IrradianceRecord& r,
                    const Vec3& p, const Vec3& n) {
    const Vec3 d = p - r.p;
    const float dist = length(d);
    const float cos_n = dot(n, r.n);
    if (cos_n <= 0.f) return 0.f;
    const float bend = std::sqrt(std::max(0.f, 1.f - cos_n));
    if (dot(d, (n + r.n) * 0.5f) < -kFrontTolerance * r.r) return 0.f;
    if (params.weight == CacheWeight::Ward) {
        const float err = dist / r.r + bend;
        // w > 1 / a  <=>  err < a.
        if (!(err < params.a)) return 0.f;
        return 1.f / std::max(err, 1e-6f);
    }
    const float radius = std::clamp(2.f * r.r_harmonic, r.r_min, r.r_max);
    const float w = 1.f - params.kappa * std::max(dist / radius, bend / normal_limit);
    return w > 0.f ? w : 0.f;
}

RGB record_extrapolate(const CacheParams& params, const IrradianceRecord& r, const Vec3& p,
                       const Vec3& n) {
    if (!params.gradients) return r.e;
    const Vec3 d = p - r.p;
    const Vec3 axis = cross(r.n, n);  // rotation taking n_i to n, by the small angle |axis|
    float e[3] = {r.e.r, r.e.g, r.e.b};
    for (int c = 0; c < 3; ++c)
        e[c] = std::max(0.f, e[c] + dot(d, r.grad_t[c]) + dot(axis, r.grad_r[c]));
    return RGB(e[0], e[1], e[2]);
}

HemisphereStrata HemisphereStrata::from_count(uint32_t samples) {
    HemisphereStrata h;
    h.m = std::max(1u, uint32_t(std::lround(std::sqrt(double(samples) / kPi))));
    h.n = std::max(1u, uint32_t(std::lround(double(samples) / h.m)));
    return h;
}

Vec3 HemisphereStrata::direction(uint32_t j, uint32_t k, Point2 u) const {
    const float s2 = (float(j) + u.x) / float(m);  // sin^2 theta
    const float sin_t = std::sqrt(s2), cos_t = std::sqrt(std::max(0.f, 1.f - s2));
    const float phi = 2.f * kPi * (float(k) + u.y) / float(n);
    return {sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t};
}

IrradianceRecord build_record(const Vec3& p, const Vec3& s, const Vec3& t, const Vec3& n,
                              const HemisphereStrata& h, const RGB* L, const float* dist,
                              RadiusRule rule, float r_min, float r_max) {
    const uint32_t M = h.m, N = h.n;
    IrradianceRecord rec;
    rec.p = p;
    rec.n = n;
    rec.r_min = r_min;
    rec.r_max = r_max;
    double sum[3] = {0, 0, 0}, inv_dist = 0.0;
    float shortest = kInfinity;
    for (uint32_t j = 0; j < M; ++j) {
        // The row's middle direction decides whether it is grazing.
        const float cos_mid = std::sqrt(std::max(0.f, 1.f - (float(j) + 0.5f) / float(M)));
        for (uint32_t k = 0; k < N; ++k) {
            const uint32_t i = j * N + k;
            sum[0] += L[i].r;
            sum[1] += L[i].g;
            sum[2] += L[i].b;
            if (std::isfinite(dist[i]) && dist[i] > 0.f) {
                inv_dist += 1.0 / dist[i];
                if (cos_mid >= kMinimumRuleCos) shortest = std::min(shortest, dist[i]);
            }
        }
    }
    const double scale = kPi / double(M * N);
    rec.e = RGB(float(sum[0] * scale), float(sum[1] * scale), float(sum[2] * scale));
    const float harmonic = inv_dist > 0.0 ? float(double(M * N) / inv_dist) : kInfinity;
    rec.r_harmonic = rule == RadiusRule::Harmonic ? harmonic : shortest;
    rec.r = std::clamp(rec.r_harmonic, r_min, r_max);

    // Ward & Heckbert (1992). Rotation: tilting the normal about a tangent axis changes
    // each stratum's cosine; per stratum of projected solid angle pi / (M N) that is
    // L tan(theta) times the tangent direction perpendicular to phi.
    // Translation: moving the point moves what each stratum sees across the strata
    // boundaries. Across the boundary between rows j-1 and j (theta_j-) the projected solid
    // angle that changes hands is sin cos^2 (theta_j-) (2 pi / N) / r per unit of motion
    // along the column's direction u_k; across the boundary between columns k-1 and k
    // (phi_k-) it is (sin theta_j+ - sin theta_j-) / r along the tangent v_k- = e_phi there.
    // r is the nearer of the two strata's distances (the closer surface occludes).
    auto ch = [](const RGB& v, int c) { return c == 0 ? v.r : c == 1 ? v.g : v.b; };
    double gr[3][2] = {}, gt[3][2] = {};
    for (uint32_t k = 0; k < N; ++k) {
        const double phi = 2.0 * kPi * (k + 0.5) / N;
        const double phi_minus = 2.0 * kPi * k / N;
        const double uk[2] = {std::cos(phi), std::sin(phi)};
        const double vk[2] = {-std::sin(phi), std::cos(phi)};
        const double vkm[2] = {-std::sin(phi_minus), std::cos(phi_minus)};
        const uint32_t kp = (k + N - 1) % N;
        for (uint32_t j = 0; j < M; ++j) {
            const uint32_t i = j * N + k;
            const double s2_mid = (j + 0.5) / M;
            const double tan_mid = std::sqrt(s2_mid / std::max(1e-12, 1.0 - s2_mid));
            const double sin_minus = std::sqrt(double(j) / M);
            const double sin_plus = std::sqrt(double(j + 1) / M);
            for (int c = 0; c < 3; ++c) {
                const double l = ch(L[i], c);
                gr[c][0] += scale * tan_mid * l * vk[0];
                gr[c][1] += scale * tan_mid * l * vk[1];
                // Column boundary phi_k- (between k-1 and k) in row j.
                const float rc = std::min(dist[i], dist[j * N + kp]);
                if (std::isfinite(rc) && rc > 0.f) {
                    const double a = (sin_plus - sin_minus) / rc * (l - ch(L[j * N + kp], c));
                    gt[c][0] += a * vkm[0];
                    gt[c][1] += a * vkm[1];
                }
                // Row boundary theta_j- (between j-1 and j) in column k.
                if (j > 0) {
                    const uint32_t below = (j - 1) * N + k;
                    const float rr = std::min(dist[i], dist[below]);
                    if (std::isfinite(rr) && rr > 0.f) {
                        const double cos2 = 1.0 - double(j) / M;
                        const double a =
                            sin_minus * cos2 * (2.0 * kPi / N) / rr * (l - ch(L[below], c));
                        gt[c][0] += a * uk[0];
                        gt[c][1] += a * uk[1];
                    }
                }
            }
        }
    }
    for (int c = 0; c < 3; ++c) {
        rec.grad_r[c] = s * float(gr[c][0]) + t * float(gr[c][1]);
        rec.grad_t[c] = s * float(gt[c][0]) + t * float(gt[c][1]);
    }
    return rec;
}

IrradianceCache::IrradianceCache(const Bounds3& bounds, const CacheParams& params)
    : bounds_(bounds), params_(params), normal_limit_(params.normal_limit()) {
    octree_.reset(bounds);
}

void IrradianceCache::clear() {
    records_.clear();
    octree_.reset(bounds_);
}

void IrradianceCache::insert(const IrradianceRecord& r) {
    const uint32_t index = uint32_t(records_.size());
    records_.push_back(r);
    octree_.insert(index, r.p, record_influence(params_, r));
}

void IrradianceCache::sort_indices(uint32_t* idx, uint32_t count) {
    std::sort(idx, idx + count);
}

}  // namespace foton
