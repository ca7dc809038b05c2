#include "photon_map.h"

#include <cmath>
#include <stdexcept>

#include "photon_direction.h"

namespace foton {

namespace {
constexpr float kGaussAlpha = 0.918f, kGaussBeta = 1.953f;

// Integral over the unit disc of the Gauss filter's weight divided by pi: the filter's own
// normalisation (0.531 for alpha = 0.918, beta = 1.953).
double gauss_integral() {
    const double b = kGaussBeta;
    const double j = 1.0 - (2.0 / b) * (1.0 - std::exp(-b / 2.0));  // of (1 - e^{-b s^2/2}) 2s
    return kGaussAlpha * (1.0 - j / (1.0 - std::exp(-b)));
}

}  // namespace

float filter_weight(const EstimateParams& p, float d, float r) {
    const float s = d / r;
    switch (p.filter) {
        case PhotonFilter::None:
            return 1.f;
        case PhotonFilter::Cone:
            // w = 1 - d / (k r), whose integral over the disc is (1 - 2 / (3k)) pi r^2.
            return (1.f - s / p.cone_k) / (1.f - 2.f / (3.f * p.cone_k));
        case PhotonFilter::Gauss:
        case PhotonFilter::GaussThesis: {
            static const float norm = float(gauss_integral());
            const float w = kGaussAlpha * (1.f - (1.f - std::exp(-kGaussBeta * s * s * 0.5f)) /
                                                     (1.f - std::exp(-kGaussBeta)));
            return p.filter == PhotonFilter::Gauss ? w / norm : w;
        }
        case PhotonFilter::Simpson: {
            // Silverman's biweight ("Simpson's") kernel 3/pi (1 - s^2)^2, times pi.
            const float u = 1.f - s * s;
            return 3.f * u * u;
        }
    }
    return 1.f;
}

void PhotonMap::reserve(std::size_t n) {
    x_.reserve(n);
    y_.reserve(n);
    z_.reserve(n);
    power_.reserve(n);
    dir_.reserve(n);
    normal_.reserve(n);
    light_.reserve(n);
    flags_.reserve(n);
}

void PhotonMap::clear() {
    x_.clear();
    y_.clear();
    z_.clear();
    power_.clear();
    dir_.clear();
    normal_.clear();
    flags_.clear();
    light_.clear();
    tree_ = {};
    irr_e_.clear();
    power_rgbe_.clear();
    irr_rgbe_.clear();
    irr_x_.clear();
    irr_y_.clear();
    irr_z_.clear();
    irr_n_.clear();
    compact_ = false;
}

void PhotonMap::compact_power() {
    if (compact_) return;
    power_rgbe_.resize(power_.size());
    for (std::size_t i = 0; i < power_.size(); ++i) power_rgbe_[i] = encode_rgbe(power_[i]);
    irr_rgbe_.resize(irr_e_.size());
    for (std::size_t i = 0; i < irr_e_.size(); ++i) irr_rgbe_[i] = encode_rgbe(irr_e_[i]);
    std::vector<RGB>().swap(power_);
    std::vector<RGB>().swap(irr_e_);
    compact_ = true;
}

void PhotonMap::push(const Vec3& p, const RGB& power, const Vec3& w, const Vec3& n, uint8_t flags,
                     uint16_t light) {
    if (compact_) throw std::logic_error("PhotonMap::push after compact_power()");
    x_.push_back(p.x);
    y_.push_back(p.y);
    z_.push_back(p.z);
    power_.push_back(power);
    dir_.push_back(encode_direction(w));
    normal_.push_back(encode_direction(n));
    flags_.push_back(flags);
    light_.push_back(light);
}

void PhotonMap::append(const PhotonMap& o) {
    if (compact_ || o.compact_) throw std::logic_error("PhotonMap::append of compact maps");
    x_.insert(x_.end(), o.x_.begin(), o.x_.end());
    y_.insert(y_.end(), o.y_.begin(), o.y_.end());
    z_.insert(z_.end(), o.z_.begin(), o.z_.end());
    power_.insert(power_.end(), o.power_.begin(), o.power_.end());
    dir_.insert(dir_.end(), o.dir_.begin(), o.dir_.end());
    normal_.insert(normal_.end(), o.normal_.begin(), o.normal_.end());
    light_.insert(light_.end(), o.light_.begin(), o.light_.end());
    flags_.insert(flags_.end(), o.flags_.begin(), o.flags_.end());
}

void PhotonMap::push_from(const PhotonMap& o, std::size_t i, float scale) {
    if (compact_ || o.compact_) throw std::logic_error("PhotonMap::push_from of compact maps");
    x_.push_back(o.x_[i]);
    y_.push_back(o.y_[i]);
    z_.push_back(o.z_[i]);
    power_.push_back(o.power_[i] * scale);
    dir_.push_back(o.dir_[i]);
    normal_.push_back(o.normal_[i]);
    flags_.push_back(o.flags_[i]);
    light_.push_back(o.light_[i]);
}

PhotonMap PhotonMap::extract(uint8_t flag) {
    if (compact_) throw std::logic_error("PhotonMap::extract after compact_power()");
    PhotonMap out;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < size(); ++i) {
        if (flags_[i] & flag) {
            out.x_.push_back(x_[i]);
            out.y_.push_back(y_[i]);
            out.z_.push_back(z_[i]);
            out.power_.push_back(power_[i]);
            out.dir_.push_back(dir_[i]);
            out.normal_.push_back(normal_[i]);
            out.light_.push_back(light_[i]);
            out.flags_.push_back(flags_[i]);
            continue;
        }
        x_[kept] = x_[i];
        y_[kept] = y_[i];
        z_[kept] = z_[i];
        power_[kept] = power_[i];
        dir_[kept] = dir_[i];
        normal_[kept] = normal_[i];
        light_[kept] = light_[i];
        flags_[kept] = flags_[i];
        ++kept;
    }
    x_.resize(kept);
    y_.resize(kept);
    z_.resize(kept);
    power_.resize(kept);
    dir_.resize(kept);
    normal_.resize(kept);
    light_.resize(kept);
    flags_.resize(kept);
    return out;
}

Vec3 PhotonMap::incident(std::size_t i) const {
    return decode_direction(dir_[i]);
}

Vec3 PhotonMap::normal(std::size_t i) const {
    return decode_direction(normal_[i]);
}

void PhotonMap::build(const kern::PointKdTree::ParallelInvoke& parallel) {
    tree_.build(x_.data(), y_.data(), z_.data(), x_.size(), parallel);
}

std::size_t PhotonMap::memory_bytes() const {
    // Position, power, direction, normal, flags and light per photon; the precomputed points.
    const std::size_t power = compact_ ? sizeof(uint32_t) : sizeof(RGB);
    return size() * (3 * sizeof(float) + power + 3 * sizeof(uint16_t) + sizeof(uint8_t)) +
           tree_.memory_bytes() + irr_x_.size() * (3 * sizeof(float) + sizeof(uint16_t) + power) +
           irr_tree_.memory_bytes();
}

RGB PhotonMap::total_power() const {
    double s[3] = {0, 0, 0};
    for (std::size_t i = 0; i < size(); ++i) {
        const RGB p = power(i);
        s[0] += p.r;
        s[1] += p.g;
        s[2] += p.b;
    }
    return RGB(float(s[0]), float(s[1]), float(s[2]));
}

uint32_t PhotonMap::gather(const Vec3& p, const Vec3& n, const EstimateParams& params,
                           uint32_t* idx, float* d2, float& radius) const {
    const float q[3] = {p.x, p.y, p.z};
    const uint32_t k = std::min(params.k, kMaxEstimate);
    const uint32_t found = tree_.knn(q, params.max_radius * params.max_radius, k, idx, d2);
    return accept(p, n, params, k, found, idx, d2, radius);
}

uint32_t PhotonMap::accept(const Vec3& p, const Vec3& n, const EstimateParams& params, uint32_t k,
                           uint32_t found, uint32_t* idx, float* d2, float& radius) const {
    if (found == 0) return 0;
    // With k photons the disc reaches the k-th; with fewer, the whole search radius was
    // searched and is the area they were found in. Taking the farthest photon's distance
    // then would turn one stray photon next to the query into a firefly.
    const bool full = found == k;
    if (params.envelope == PhotonEnvelope::Sphere) {
        radius = full ? std::sqrt(d2[0]) : params.max_radius;  // max-heap: farthest first
        return found;
    }
    // Disc: keep the photons near the tangent plane (the flattened ellipsoid of the thesis);
    // the radius is then the farthest photon kept.
    const float limit = params.disc_thickness * std::sqrt(d2[0]);
    uint32_t kept = 0;
    float r2 = 0.f;
    for (uint32_t i = 0; i < found; ++i) {
        const Vec3 v = position(idx[i]) - p;
        if (std::fabs(dot(v, n)) > limit) continue;
        idx[kept] = idx[i];
        d2[kept] = d2[i];
        r2 = std::max(r2, d2[i]);
        ++kept;
    }
    radius = full ? std::sqrt(r2) : params.max_radius;
    return kept;
}

RGB PhotonMap::radiance(const Vec3& p, const Vec3& s, const Vec3& t, const Vec3& n,
                        const Bsdf& bsdf, const Vec3& wo, const BsdfContext& ctx,
                        const EstimateParams& params, uint32_t* found) const {
    uint32_t idx[kMaxEstimate];
    float d2[kMaxEstimate];
    float r = 0.f;
    const uint32_t m = gather(p, n, params, idx, d2, r);
    if (found) *found = m;
    return radiance_of(s, t, n, bsdf, wo, ctx, params, m, idx, d2, r);
}

void PhotonMap::knn_batch(const float* x, const float* y, const float* z, std::size_t count,
                          const EstimateParams& params, kern::KnnBatchResult& out) const {
    const std::vector<float> max_d2(count, params.max_radius * params.max_radius);
    tree_.knn_batch(x, y, z, max_d2.data(), count, std::min(params.k, kMaxEstimate), out);
}

RGB PhotonMap::radiance_from(const Vec3& p, const Vec3& s, const Vec3& t, const Vec3& n,
                             const Bsdf& bsdf, const Vec3& wo, const BsdfContext& ctx,
                             const EstimateParams& params, uint32_t found, uint32_t* idx,
                             float* d2) const {
    float r = 0.f;
    const uint32_t m = accept(p, n, params, std::min(params.k, kMaxEstimate), found, idx, d2, r);
    return radiance_of(s, t, n, bsdf, wo, ctx, params, m, idx, d2, r);
}

RGB PhotonMap::radiance_of(const Vec3& s, const Vec3& t, const Vec3& n, const Bsdf& bsdf,
                           const Vec3& wo, const BsdfContext& ctx, const EstimateParams& params,
                           uint32_t m, const uint32_t* idx, const float* d2, float r) const {
    if (m == 0 || !(r > 0.f)) return RGB{0.f};
    RGB sum;
    for (uint32_t i = 0; i < m; ++i) {
        const Vec3 w = incident(idx[i]);
        const float cn = dot(w, n);
        // Arrived from behind this surface: only a rough dielectric lets it through.
        if (cn <= 0.f && (cn == 0.f || !bsdf.transmits_non_delta())) continue;
        const Vec3 wl{dot(w, s), dot(w, t), cn};
        const RGB f = bsdf.f(wo, wl, ctx);
        sum += f * power(idx[i]) * filter_weight(params, std::sqrt(d2[i]), r);
    }
    return sum * (1.f / (kPi * r * r));
}

RGB PhotonMap::irradiance(const Vec3& p, const Vec3& n, const EstimateParams& params,
                          uint32_t* found) const {
    uint32_t idx[kMaxEstimate];
    float d2[kMaxEstimate];
    float r = 0.f;
    const uint32_t m = gather(p, n, params, idx, d2, r);
    if (found) *found = m;
    return irradiance_of(n, params, m, idx, d2, r);
}

RGB PhotonMap::irradiance_of(const Vec3& n, const EstimateParams& params, uint32_t m,
                             const uint32_t* idx, const float* d2, float r) const {
    if (m == 0 || !(r > 0.f)) return RGB{0.f};
    RGB sum;
    for (uint32_t i = 0; i < m; ++i) {
        if (dot(incident(idx[i]), n) <= 0.f) continue;
        sum += power(idx[i]) * filter_weight(params, std::sqrt(d2[i]), r);
    }
    return sum * (1.f / (kPi * r * r));
}

}  // namespace foton
