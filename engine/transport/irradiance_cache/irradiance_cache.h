#pragma once
// Ward's irradiance cache, as the lecture notes give it (NPGR010, 2011): records of
// irradiance computed by stratified hemisphere sampling at a few points, each valid within a
// radius derived from the distances its sample rays travelled, and interpolated elsewhere
// with Ward & Heckbert's translation and rotation gradients. Records live in an octree
// (record_octree.h); a brute-force scan over all records is kept as the tests' oracle.
#include <cstdint>
#include <vector>

#include "engine/core/math.h"
#include "engine/core/rgb.h"
#include "engine/core/sampler.h"
#include "engine/core/stats.h"
#include "engine/transport/irradiance_cache/record_octree.h"

namespace foton {

enum class CacheWeight : uint8_t {
    Ward,   // w = 1 / (|p - p_i| / R_i + sqrt(1 - n . n_i)), used where w > 1 / a
    Notes,  // w = 1 - kappa max(|p - p_i| / clamp(2 R_i, R_min, R_max),
            //                   sqrt(1 - n . n_i) / sqrt(1 - cos 10 deg)), used where w > 0
};

struct CacheParams {
    CacheWeight weight = CacheWeight::Notes;
    float a = 0.3f;              // Ward's accuracy: records are used out to a R_i
    float kappa = 1.f;           // the notes' accuracy: larger kappa, smaller neighbourhoods
    float max_angle_deg = 10.f;  // the notes' normal limit
    bool gradients = true;
    // sqrt(1 - cos max_angle): the notes' normal term at the limit.
    float normal_limit() const;
};

struct IrradianceRecord {
    Vec3 p, n;               // position and the normal of the side it was computed on
    RGB e;                   // irradiance
    float r = 0.f;           // validity radius R_i, clamped to [r_min, r_max]
    float r_harmonic = 0.f;  // the harmonic-mean (or minimum) distance before clamping
    float r_min = 0.f, r_max = 0.f;
    Vec3 grad_t[3];  // translation gradient per channel (world space, dE / dx)
    Vec3 grad_r[3];  // rotation gradient per channel (world space, dE / d angle about axis)
};

// The record's weight at (p, n), or 0 when the record must not be used there.
float record_weight(const CacheParams& params, const IrradianceRecord& r, const Vec3& p,
                    const Vec3& n);
// The same with params.normal_limit() computed by the caller (once per lookup).
float record_weight(const CacheParams& params, float normal_limit, const IrradianceRecord& r,
                    const Vec3& p, const Vec3& n);
// The radius beyond which record_weight is always 0 (the octree's sphere).
float record_influence(const CacheParams& params, const IrradianceRecord& r);
// The record's irradiance extrapolated to (p, n) by its gradients (when enabled).
RGB record_extrapolate(const CacheParams& params, const IrradianceRecord& r, const Vec3& p,
                       const Vec3& n);

// How a record's sample directions are laid out: M rows in theta (cosine-weighted strata,
// theta_j = asin(sqrt((j + u) / M))) times N columns in phi.
struct HemisphereStrata {
    uint32_t m = 16, n = 50;
    // Rows and columns for about `samples` rays with N ~ pi M (square strata on the disc).
    static HemisphereStrata from_count(uint32_t samples);
    uint32_t count() const { return m * n; }
    // Local direction (z = normal) of stratum (j, k) jittered by u in [0, 1)^2.
    Vec3 direction(uint32_t j, uint32_t k, Point2 u) const;
};

// The validity radius from the sample rays' hit distances (infinite for a miss).
enum class RadiusRule : uint8_t {
    Harmonic,  // M N / sum(1 / r_jk): the notes' (and Ward's) rule
    Minimum,   // the shortest ray within 60 degrees of the normal (grazing rays ignored)
};

// Builds a record at p from the radiance L[j * N + k] and distance dist[j * N + k] seen by
// the stratum (j, k) rays (local frame s, t, n): E = pi / (M N) sum L, the radius by `rule`
// clamped to [r_min, r_max], and Ward & Heckbert's gradients.
IrradianceRecord build_record(const Vec3& p, const Vec3& s, const Vec3& t, const Vec3& n,
                              const HemisphereStrata& strata, const RGB* L, const float* dist,
                              RadiusRule rule, float r_min, float r_max);

class IrradianceCache {
  public:
    IrradianceCache(const Bounds3& bounds, const CacheParams& params);
    // Empties the cache (keeping its bounds and parameters).
    void clear();
    const CacheParams& params() const { return params_; }
    void insert(const IrradianceRecord& r);
    std::size_t size() const { return records_.size(); }
    const IrradianceRecord& record(std::size_t i) const { return records_[i]; }
    const RecordOctree& octree() const { return octree_; }

    // The weighted mean of the extrapolated irradiance of every record with positive weight
    // at (p, n) whose `visible(record)` holds, here and in `also` (a second cache, e.g. the
    // records of the current batch); false (and e = 0) when there is none. The records are
    // summed in index order, so the octree and the scan agree exactly.
    template <class Visible>
    bool interpolate(const Vec3& p, const Vec3& n, RGB& e, Visible&& visible, CacheCounters& st,
                     const IrradianceCache* also = nullptr) const {
        Blend b;
        ++st.lookups;
        add_candidates(p, n, visible, st, b);
        if (also) also->add_candidates(p, n, visible, st, b);
        return b.finish(e, st);
    }
    // The same over all records (the oracle).
    template <class Visible>
    bool interpolate_brute(const Vec3& p, const Vec3& n, RGB& e, Visible&& visible,
                           CacheCounters& st) const {
        std::vector<uint32_t> idx(records_.size());
        for (uint32_t i = 0; i < idx.size(); ++i) idx[i] = i;
        Blend b;
        ++st.lookups;
        add(p, n, idx.data(), uint32_t(idx.size()), visible, st, b);
        return b.finish(e, st);
    }

    // interpolate() in two steps, for lookups served as a batch: the records that may take
    // part at (p, n), in the order interpolate() sums them (appended to `out`); then the
    // interpolation from those of them whose visibility test passed.
    void candidates(const Vec3& p, const Vec3& n, std::vector<uint32_t>& out,
                    CacheCounters& st) const {
        uint32_t idx[kMaxCandidates];
        uint32_t count = 0;
        octree_.for_each_candidate(p, [&](uint32_t i) {
            if (count < kMaxCandidates) idx[count++] = i;
        });
        const uint32_t kept = keep_weighted(p, n, idx, count, st);
        out.insert(out.end(), idx, idx + kept);
    }
    // Sums records idx[i] with visible[i] into the running blend `b` (start with Blend{}).
    struct Blend;
    void blend_visible(const Vec3& p, const Vec3& n, const uint32_t* idx, const uint8_t* visible,
                       std::size_t count, CacheCounters& st, Blend& b) const {
        for (std::size_t i = 0; i < count; ++i)
            if (visible[i]) blend(p, n, records_[idx[i]], st, b);
    }

  private:
    static constexpr uint32_t kMaxCandidates = 4096;

  public:
    // The running weighted sum of an interpolation.
    struct Blend {
        double sum[3] = {0.0, 0.0, 0.0}, wsum = 0.0;
        bool finish(RGB& e, CacheCounters& st) const {
            if (!(wsum > 0.0)) {
                e = RGB{0.f};
                return false;
            }
            ++st.interpolated;
            e = RGB(float(sum[0] / wsum), float(sum[1] / wsum), float(sum[2] / wsum));
            return true;
        }
    };

  private:
    template <class Visible>
    void add_candidates(const Vec3& p, const Vec3& n, Visible&& visible, CacheCounters& st,
                        Blend& b) const {
        uint32_t idx[kMaxCandidates];
        uint32_t count = 0;
        octree_.for_each_candidate(p, [&](uint32_t i) {
            if (count < kMaxCandidates) idx[count++] = i;
        });
        add(p, n, idx, count, visible, st, b);
    }
    template <class Visible>
    void add(const Vec3& p, const Vec3& n, uint32_t* idx, uint32_t count, Visible&& visible,
             CacheCounters& st, Blend& b) const {
        const uint32_t kept = keep_weighted(p, n, idx, count, st);
        for (uint32_t c = 0; c < kept; ++c) {
            const IrradianceRecord& r = records_[idx[c]];
            if (visible(r)) blend(p, n, r, st, b);
        }
    }
    // Weighs every candidate, keeps those with positive weight in place, and sorts only them
    // into index order (the octree finds far more candidates than it keeps).
    uint32_t keep_weighted(const Vec3& p, const Vec3& n, uint32_t* idx, uint32_t count,
                           CacheCounters& st) const {
        st.candidates += count;
        uint32_t kept = 0;
        for (uint32_t c = 0; c < count; ++c)
            if (record_weight(params_, normal_limit_, records_[idx[c]], p, n) > 0.f)
                idx[kept++] = idx[c];
        sort_indices(idx, kept);
        return kept;
    }
    void blend(const Vec3& p, const Vec3& n, const IrradianceRecord& r, CacheCounters& st,
               Blend& b) const {
        const float w = record_weight(params_, normal_limit_, r, p, n);
        const RGB v = record_extrapolate(params_, r, p, n);
        b.sum[0] += double(w) * v.r;
        b.sum[1] += double(w) * v.g;
        b.sum[2] += double(w) * v.b;
        b.wsum += w;
        ++st.used;
    }
    static void sort_indices(uint32_t* idx, uint32_t count);

    Bounds3 bounds_;
    CacheParams params_;
    float normal_limit_;
    std::vector<IrradianceRecord> records_;
    RecordOctree octree_;
};

}  // namespace foton
