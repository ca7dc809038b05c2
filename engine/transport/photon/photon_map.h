#pragma once
// A photon map (Jensen): photons stored in SoA (position, power, incident direction
// compressed to two bytes, flags), balanced into the kernels' left-balanced kd-tree with SIMD
// leaf buckets, and the radiance estimate of the photon-mapping thesis (chapters 5.4, 6.1):
// the k nearest photons within a maximum radius, a sphere or disc (flattened ellipsoid)
// envelope, back-face rejection by the surface normal, and the none / cone / Gauss / Simpson
// filters, each normalised so that its kernel integrates to one over the disc.
#include <algorithm>
#include <cstdint>
#include <functional>
#include <vector>

#include "engine/core/aligned.h"
#include "engine/core/cluster.h"
#include "engine/core/math.h"
#include "engine/core/rgb.h"
#include "engine/core/rgbe.h"
#include "engine/scene/bsdf.h"
#include "engine/transport/photon/photon_settings.h"
#include "kernels/point_kdtree.h"

namespace foton {

struct EstimateParams {
    uint32_t k = 100;        // photons in an estimate
    float max_radius = 1.f;  // search radius limit (scene units)
    PhotonEnvelope envelope = PhotonEnvelope::Disc;
    float disc_thickness = 0.1f;  // disc: photons farther than this x radius from the plane
                                  // are rejected (the flattened ellipsoid)
    PhotonFilter filter = PhotonFilter::None;
    float cone_k = 1.1f;  // cone filter constant, >= 1
};

// The filter kernel's weight for a photon at distance d in a disc of radius r, already
// divided by the kernel's integral over the disc, so sum(w * power * f) / (pi r^2) is the
// estimate for every filter (the thesis' Gauss filter with alpha = 0.918 integrates to 0.53
// over the disc with its 1 / (pi r^2), which is why it darkened the thesis' images).
float filter_weight(const EstimateParams& p, float d, float r);

// kPhotonViaSpecular: the photon's last bounce was off a delta lobe (a mirror or glass), the
// light next event estimation cannot sample; every caustic photon has it.
enum PhotonFlags : uint8_t {
    kPhotonCaustic = 1,
    kPhotonDirect = 2,
    kPhotonShadow = 4,
    kPhotonViaSpecular = 8
};

class PhotonMap {
  public:
    static constexpr uint32_t kMaxEstimate = 4096;  // photons in one estimate, at most

    void reserve(std::size_t n);
    void clear();
    // `normal`: the surface's geometric normal on the side the photon arrived from.
    void push(const Vec3& p, const RGB& power, const Vec3& incident, const Vec3& normal,
              uint8_t flags, uint16_t light = 0);
    // Appends another map's photons (before build).
    void append(const PhotonMap& other);
    // Appends photon i of another map with its power times `scale` (before build).
    void push_from(const PhotonMap& other, std::size_t i, float scale);
    // Replaces the photons, on every MPI rank of `cluster`, by every rank's in rank order
    // (before build). Collective.
    void all_gather(const Cluster& cluster);
    // Moves the photons with any of `flag`'s bits into the returned map, in order (before
    // build).
    PhotonMap extract(uint8_t flag);
    // Balances the kd-tree; `parallel` runs two jobs (timed_parallel_invoke in the engine:
    // core/thread_clock.h).
    void build(const kern::PointKdTree::ParallelInvoke& parallel = {});

    std::size_t size() const { return x_.size(); }
    bool empty() const { return x_.empty(); }
    std::size_t memory_bytes() const;
    Vec3 position(std::size_t i) const { return {x_[i], y_[i], z_[i]}; }
    RGB power(std::size_t i) const { return compact_ ? decode_rgbe(power_rgbe_[i]) : power_[i]; }
    // Ward's shared-exponent RGBE (core/rgbe.h) for the photons' power and the precomputed
    // irradiance from here on, 4 bytes each instead of 12 (the photon thesis' 6.5, Jensen's
    // photon struct): after the map's photons are final (appended, gathered, split), before or
    // after build.
    void compact_power();
    bool compact() const { return compact_; }
    Vec3 incident(std::size_t i) const;  // unit, pointing away from the surface (to the light)
    Vec3 normal(std::size_t i) const;
    uint8_t flags(std::size_t i) const { return flags_[i]; }
    uint16_t light(std::size_t i) const { return light_[i]; }  // the emitter it came from
    RGB total_power() const;

    // Reflected radiance at p towards wo (local to the shading frame s, t, n, whose normal
    // faces the viewer's side) from the photons: sum of f(wo, wi_p) * power_p * filter /
    // (pi r^2), with photons arriving from behind the surface (wi_p . n <= 0) rejected.
    RGB radiance(const Vec3& p, const Vec3& s, const Vec3& t, const Vec3& n, const Bsdf& bsdf,
                 const Vec3& wo_local, const BsdfContext& ctx, const EstimateParams& params,
                 uint32_t* found = nullptr) const;
    // radiance() in two steps, for estimates made as a batch: the kNN of `count` queries at
    // once (Morton-ordered, kern::PointKdTree::knn_batch; k and radius from params), then
    // each estimate from its row of the result (its idx/d2 are compacted in place).
    void knn_batch(const float* x, const float* y, const float* z, std::size_t count,
                   const EstimateParams& params, kern::KnnBatchResult& out) const;
    RGB radiance_from(const Vec3& p, const Vec3& s, const Vec3& t, const Vec3& n, const Bsdf& bsdf,
                      const Vec3& wo_local, const BsdfContext& ctx, const EstimateParams& params,
                      uint32_t found, uint32_t* idx, float* d2) const;
    // Irradiance E at p with normal n (the estimate with f = 1/pi removed: sum power / pi r^2).
    RGB irradiance(const Vec3& p, const Vec3& n, const EstimateParams& params,
                   uint32_t* found = nullptr) const;

    // Calls f(photon index) for each of the (up to) k photons nearest to p within radius r.
    template <class F>
    void for_each_nearest(const Vec3& p, uint32_t k, float r, F&& f) const {
        constexpr uint32_t kMax = 64;
        uint32_t idx[kMax];
        float d2[kMax];
        const float q[3] = {p.x, p.y, p.z};
        const uint32_t n = tree_.knn(q, r * r, std::min(k, kMax), idx, d2);
        for (uint32_t i = 0; i < n; ++i) f(idx[i]);
    }

    // Calls f(photon index) for each photon an estimate at p with normal n would use (the
    // k nearest within the envelope; back-facing ones included).
    template <class F>
    void for_each_estimate_photon(const Vec3& p, const Vec3& n, const EstimateParams& params,
                                  F&& f) const {
        uint32_t idx[kMaxEstimate];
        float d2[kMaxEstimate];
        float r = 0.f;
        const uint32_t m = gather(p, n, params, idx, d2, r);
        for (uint32_t i = 0; i < m; ++i) f(idx[i]);
    }

    // Calls f(photon index, squared distance) for every photon within radius r of p.
    template <class F>
    void for_each_in_radius(const Vec3& p, float r, F&& f) const {
        const float q[3] = {p.x, p.y, p.z};
        tree_.for_each_in_radius(q, r * r, f);
    }

    // Christensen's precomputed irradiance: E at every `stride`-th photon (with its normal),
    // computed in parallel by `parallel_for(n, body(begin, end))`, kept in its own kd-tree;
    // across the MPI ranks of `cluster`, each computes a share and all get every value.
    using ParallelFor =
        std::function<void(std::size_t, const std::function<void(std::size_t, std::size_t)>&)>;
    void precompute_irradiance(uint32_t stride, const EstimateParams& params,
                               const ParallelFor& parallel_for, const Cluster* cluster = nullptr);
    bool has_precomputed() const { return !irr_x_.empty(); }
    std::size_t precomputed_size() const { return irr_x_.size(); }
    // The precomputed irradiance nearest to p among those within max_radius whose normal is
    // within ~25 degrees of n; false when there is none.
    bool lookup_irradiance(const Vec3& p, const Vec3& n, float max_radius, RGB& e) const;
    // The same for a batch of queries in SoA, served at once by the kd-tree's batched kNN
    // (Morton-ordered): found[i] and e[i] are what lookup_irradiance gives for query i.
    struct IrradianceQueries {
        std::vector<float> x, y, z, max_d2;
        std::vector<Vec3> n;
        kern::KnnBatchResult knn;
        void clear() {
            x.clear();
            y.clear();
            z.clear();
            max_d2.clear();
            n.clear();
        }
        void push(const Vec3& p, const Vec3& normal, float max_radius) {
            x.push_back(p.x);
            y.push_back(p.y);
            z.push_back(p.z);
            max_d2.push_back(max_radius * max_radius);
            n.push_back(normal);
        }
        std::size_t size() const { return x.size(); }
    };
    void lookup_irradiance_batch(IrradianceQueries& q, std::vector<RGB>& e,
                                 std::vector<uint8_t>& found) const;

  private:
    static constexpr uint32_t kIrradianceCandidates = 8;
    // Among kNN candidates of the precomputed points: the nearest whose normal agrees with n.
    int best_irradiance(const uint32_t* idx, const float* d2, uint32_t found, const Vec3& n) const;
    // The accepted photons among `found` kNN results (k asked) for a query at p with normal n:
    // compacts idx/d2 in place, sets the radius, returns how many.
    uint32_t accept(const Vec3& p, const Vec3& n, const EstimateParams& params, uint32_t k,
                    uint32_t found, uint32_t* idx, float* d2, float& radius) const;
    RGB radiance_of(const Vec3& s, const Vec3& t, const Vec3& n, const Bsdf& bsdf, const Vec3& wo,
                    const BsdfContext& ctx, const EstimateParams& params, uint32_t m,
                    const uint32_t* idx, const float* d2, float r) const;
    RGB irradiance_of(const Vec3& n, const EstimateParams& params, uint32_t m, const uint32_t* idx,
                      const float* d2, float r) const;
    // Gathers the accepted photons of an estimate: indices, squared distances and the radius.
    uint32_t gather(const Vec3& p, const Vec3& n, const EstimateParams& params, uint32_t* idx,
                    float* d2, float& radius) const;

    AlignedVector<float> x_, y_, z_;
    std::vector<RGB> power_;
    std::vector<uint32_t> power_rgbe_;  // instead of power_ once compact
    bool compact_ = false;
    std::vector<uint16_t> dir_;     // theta, phi bytes (Jensen)
    std::vector<uint16_t> normal_;  // same encoding as dir_
    std::vector<uint8_t> flags_;
    std::vector<uint16_t> light_;
    kern::PointKdTree tree_;
    // Precomputed irradiance points.
    AlignedVector<float> irr_x_, irr_y_, irr_z_;
    std::vector<uint16_t> irr_n_;
    std::vector<RGB> irr_e_;
    std::vector<uint32_t> irr_rgbe_;  // instead of irr_e_ once compact
    RGB irr(std::size_t i) const { return compact_ ? decode_rgbe(irr_rgbe_[i]) : irr_e_[i]; }
    kern::PointKdTree irr_tree_;
};

}  // namespace foton
