#include "photon_map.h"

#include <cmath>

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
}

namespace {
// Jensen's two-byte direction: theta and phi quantised to 256 steps each.
uint16_t encode_direction(const Vec3& w) {
    const float theta = std::acos(std::clamp(w.z, -1.f, 1.f));
    float phi = std::atan2(w.y, w.x);
    if (phi < 0.f) phi += 2.f * kPi;
    const uint16_t t = uint16_t(std::min(255.f, theta * (256.f / kPi)));
    const uint16_t f = uint16_t(std::min(255.f, phi * (256.f / (2.f * kPi))));
    return uint16_t(t << 8 | f);
}

// Decoding runs for every photon of every estimate (radiance, SPPM gathering, shadow-photon
// tests), so it reads Jensen's tables of the 256 bin centres' sines and cosines.
struct DirectionTables {
    float sin_theta[256], cos_theta[256], sin_phi[256], cos_phi[256];
    DirectionTables() {
        for (int i = 0; i < 256; ++i) {
            const float theta = (float(i) + 0.5f) * (kPi / 256.f);
            const float phi = (float(i) + 0.5f) * (2.f * kPi / 256.f);
            sin_theta[i] = std::sin(theta);
            cos_theta[i] = std::cos(theta);
            sin_phi[i] = std::sin(phi);
            cos_phi[i] = std::cos(phi);
        }
    }
};
const DirectionTables kDirections;

Vec3 decode_direction(uint16_t d) {
    const int t = d >> 8, f = d & 255;
    const float st = kDirections.sin_theta[t];
    return {st * kDirections.cos_phi[f], st * kDirections.sin_phi[f], kDirections.cos_theta[t]};
}
}  // namespace

void PhotonMap::push(const Vec3& p, const RGB& power, const Vec3& w, const Vec3& n, uint8_t flags,
                     uint16_t light) {
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
    x_.insert(x_.end(), o.x_.begin(), o.x_.end());
    y_.insert(y_.end(), o.y_.begin(), o.y_.end());
    z_.insert(z_.end(), o.z_.begin(), o.z_.end());
    power_.insert(power_.end(), o.power_.begin(), o.power_.end());
    dir_.insert(dir_.end(), o.dir_.begin(), o.dir_.end());
    normal_.insert(normal_.end(), o.normal_.begin(), o.normal_.end());
    light_.insert(light_.end(), o.light_.begin(), o.light_.end());
    flags_.insert(flags_.end(), o.flags_.begin(), o.flags_.end());
}

PhotonMap PhotonMap::extract(uint8_t flag) {
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

void PhotonMap::precompute_irradiance(uint32_t stride, const EstimateParams& params,
                                      const ParallelFor& parallel_for, const Cluster* cluster) {
    const std::size_t m = stride == 0 ? 0 : (size() + stride - 1) / stride;
    irr_x_.resize(m);
    irr_y_.resize(m);
    irr_z_.resize(m);
    irr_n_.resize(m);
    irr_e_.resize(m);
    for (std::size_t j = 0; j < m; ++j) {
        const std::size_t i = j * stride;
        irr_x_[j] = x_[i];
        irr_y_[j] = y_[i];
        irr_z_[j] = z_[i];
        irr_n_[j] = normal_[i];
    }
    // The estimates run in Morton order of their points, each parallel chunk as one batched
    // kNN: a chunk's queries are then neighbours and share the tree's nodes in cache. Every
    // estimate still lands at its own point, so the order changes nothing but the speed.
    const std::vector<uint32_t> order =
        kern::morton_order(irr_x_.data(), irr_y_.data(), irr_z_.data(), m);
    const uint32_t k = std::min(params.k, kMaxEstimate);
    auto body = [&](std::size_t begin, std::size_t end) {
        const std::size_t count = end - begin;
        std::vector<float> qx(count), qy(count), qz(count),
            max_d2(count, params.max_radius * params.max_radius);
        for (std::size_t t = 0; t < count; ++t) {
            const uint32_t j = order[begin + t];
            qx[t] = irr_x_[j];
            qy[t] = irr_y_[j];
            qz[t] = irr_z_[j];
        }
        kern::KnnBatchResult res;
        tree_.knn_batch(qx.data(), qy.data(), qz.data(), max_d2.data(), count, k, res);
        for (std::size_t t = 0; t < count; ++t) {
            const uint32_t j = order[begin + t];
            const std::size_t i = std::size_t(j) * stride;
            uint32_t* idx = res.index.data() + t * k;
            float* d2 = res.dist2.data() + t * k;
            float r = 0.f;
            const Vec3 n = normal(i);
            const uint32_t kept = accept(position(i), n, params, k, res.count[t], idx, d2, r);
            irr_e_[j] = irradiance_of(n, params, kept, idx, d2, r);
        }
    };
    // Across MPI ranks each estimates a share of the points; all get every estimate.
    const Cluster& ranks = cluster_or_solo(cluster);
    const Share mine = share_of(m, ranks);
    if (parallel_for)
        parallel_for(mine.size(),
                     [&](std::size_t b, std::size_t e) { body(mine.begin + b, mine.begin + e); });
    else
        body(mine.begin, mine.end);
    if (ranks.distributed()) {
        Bytes part;
        for (std::size_t t = mine.begin; t < mine.end; ++t) foton::pack(part, &irr_e_[order[t]], 1);
        std::size_t t = 0;
        for (const Bytes& b : ranks.all_gather(part))
            for (Unpacker in(b); !in.done(); ++t) in.read(&irr_e_[order[t]], 1);
    }
    irr_tree_.build(irr_x_.data(), irr_y_.data(), irr_z_.data(), m);
}

int PhotonMap::best_irradiance(const uint32_t* idx, const float* d2, uint32_t found,
                               const Vec3& n) const {
    int best = -1;
    float best_d2 = kInfinity;
    for (uint32_t i = 0; i < found; ++i) {
        // Normals agree within ~25 degrees (two-byte normals are good to about a degree).
        if (dot(decode_direction(irr_n_[idx[i]]), n) < 0.9f) continue;
        if (d2[i] < best_d2) {
            best_d2 = d2[i];
            best = int(idx[i]);
        }
    }
    return best;
}

bool PhotonMap::lookup_irradiance(const Vec3& p, const Vec3& n, float max_radius, RGB& e) const {
    uint32_t idx[kIrradianceCandidates];
    float d2[kIrradianceCandidates];
    const float q[3] = {p.x, p.y, p.z};
    const uint32_t found =
        irr_tree_.knn(q, max_radius * max_radius, kIrradianceCandidates, idx, d2);
    const int best = best_irradiance(idx, d2, found, n);
    if (best < 0) return false;
    e = irr_e_[std::size_t(best)];
    return true;
}

void PhotonMap::lookup_irradiance_batch(IrradianceQueries& q, std::vector<RGB>& e,
                                        std::vector<uint8_t>& found) const {
    const std::size_t n = q.size();
    irr_tree_.knn_batch(q.x.data(), q.y.data(), q.z.data(), q.max_d2.data(), n,
                        kIrradianceCandidates, q.knn);
    e.resize(n);
    found.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t row = i * kIrradianceCandidates;
        const int best = best_irradiance(q.knn.index.data() + row, q.knn.dist2.data() + row,
                                         q.knn.count[i], q.n[i]);
        found[i] = best >= 0;
        if (best >= 0) e[i] = irr_e_[std::size_t(best)];
    }
}

void PhotonMap::build(const kern::PointKdTree::ParallelInvoke& parallel) {
    tree_.build(x_.data(), y_.data(), z_.data(), x_.size(), parallel);
}

std::size_t PhotonMap::memory_bytes() const {
    return size() * (3 * sizeof(float) + sizeof(RGB) + 3) + tree_.memory_bytes();
}

RGB PhotonMap::total_power() const {
    double s[3] = {0, 0, 0};
    for (const RGB& p : power_) {
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
        sum += f * power_[idx[i]] * filter_weight(params, std::sqrt(d2[i]), r);
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
        sum += power_[idx[i]] * filter_weight(params, std::sqrt(d2[i]), r);
    }
    return sum * (1.f / (kPi * r * r));
}

}  // namespace foton
