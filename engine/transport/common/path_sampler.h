#pragma once
// A camera path's random numbers, with the sampler's kind chosen once per sample (not on every
// number): counter-based uniforms keyed by the path (random, jittered, regular, hammersley:
// their pattern places the pixel sample only), Halton (one prime base per dimension after the
// pixel's two), or Sobol' / Z-order Sobol' pairs.
//
// Dimensions per bounce: light choice, light position (3), BSDF lobe and direction (3),
// Russian roulette. Sobol' takes them in pairs: the light position and the BSDF direction are
// pairs of their own, the 1D choices paired up (light choice with the mesh's triangle, lobe
// with roulette). Pair 0 is the pixel position.
#include <cstdint>

#include "engine/core/halton.h"
#include "engine/core/math.h"
#include "engine/core/rng.h"
#include "engine/core/rng_streams.h"
#include "engine/core/sampler.h"
#include "engine/core/sobol.h"
#include "engine/core/zsobol.h"
#include "engine/transport/common/camera_integrator.h"
#include "engine/transport/common/primary_vector.h"

namespace foton {

inline constexpr uint32_t kPathDimsPerBounce = 8;
inline constexpr uint32_t kPathDimLightSelect = 0, kPathDimLight = 1, kPathDimBsdf = 4,
                          kPathDimRoulette = 7;

class PathSampler {
  public:
    PathSampler() = default;
    // Counter-based numbers keyed by `path_key` and the render's seed.
    static PathSampler uniform(uint64_t path_key, uint64_t seed) {
        PathSampler s;
        s.key_ = path_key;
        s.prefix_ = rng::stream_prefix(seed, kPathStream);
        return s;
    }
    // Numbers of a Markov chain's primary-sample vector (Metropolis light transport: number k
    // of bounce d is v[offset + d * kPathDimsPerBounce + k], made as the path reads it,
    // primary_vector.h); the vector outlives the sampler and only this path reads it.
    static PathSampler primary(PrimaryVector* v, uint32_t offset, uint64_t path_key,
                               uint64_t seed) {
        PathSampler s = uniform(path_key, seed);
        s.kind_ = Kind::Primary;
        s.primary_ = v;
        s.n_ = offset;
        return s;
    }
    // A camera sample's numbers under the renderer's sampler.
    static PathSampler for_job(SamplerKind sampler, const Scene& scene, const SampleJob& job,
                               uint64_t seed) {
        PathSampler s = uniform(job.id, seed);
        if (job.pat_n == 0) return s;
        if (sampler == SamplerKind::Sobol || sampler == SamplerKind::Halton) {
            s.kind_ = sampler == SamplerKind::Sobol ? Kind::Sobol : Kind::Halton;
            s.key_ = pixel_pattern_key(scene, job);
        } else if (sampler == SamplerKind::ZSobol) {
            s.kind_ = Kind::ZSobol;
            s.key_ = 0;
            s.z_ = zsobol_index(scene, job, seed);
        } else {
            return s;
        }
        s.i_ = job.pat_i;
        s.n_ = job.pat_n;
        return s;
    }

    // Counter-based numbers (random, jittered, regular, hammersley past the pixel): number k
    // of bounce d is rng::uniform_from(prefix(), key(), d * kPathDimsPerBounce + k), which a
    // caller may draw for many paths at once (kern::uniform_table).
    bool counter_based() const { return kind_ == Kind::Uniform; }
    // Sobol' (sampler="sobol"): number k of bounce d is coordinate kCoord[k] of point
    // pattern_index() of pattern_count() of pair pair_of(d, k), keyed by key()
    // (kern::sobol::sample_table draws them for many paths at once).
    bool sobol() const { return kind_ == Kind::Sobol; }
    // Z-Sobol': the same pairs of the sample's place in the image-wide sequence.
    bool zsobol() const { return kind_ == Kind::ZSobol; }
    // Halton: number k of bounce d is dimension 2 + d * kPathDimsPerBounce + k of point
    // pattern_index() keyed by key() (kern::halton::sample_table draws them for many paths).
    bool halton() const { return kind_ == Kind::Halton; }
    const zsobol::Index& z_index() const { return z_; }
    uint32_t pattern_index() const { return i_; }
    uint32_t pattern_count() const { return n_; }
    uint64_t key() const { return key_; }
    uint64_t prefix() const { return prefix_; }

    // Number k of bounce `depth`.
    float get1(uint64_t seed, uint32_t depth, uint32_t k) const {
        switch (kind_) {
            case Kind::Uniform:
                // rng::uniform(seed, kPathStream, key_, dim), its seed's half done once.
                return rng::uniform_from(prefix_, key_, uint64_t(depth) * kPathDimsPerBounce + k);
            case Kind::Halton:
                return halton::sample(i_, seed, key_, 2 + depth * kPathDimsPerBounce + k);
            case Kind::ZSobol:
                return zsobol::sample1(z_, pair_of(depth, k), kCoord[k]);
            case Kind::Primary:
                return primary_->get(n_ + depth * kPathDimsPerBounce + k);
            case Kind::Sobol:
                break;
        }
        return sobol::sample1(i_, n_, seed, key_, pair_of(depth, k), kCoord[k]);
    }
    // Numbers k and k + 1 together (the light position, the BSDF direction): one Sobol' pair.
    Point2 get2(uint64_t seed, uint32_t depth, uint32_t k) const {
        if (kind_ == Kind::Uniform || kind_ == Kind::Halton || kind_ == Kind::Primary)
            return {get1(seed, depth, k), get1(seed, depth, k + 1)};
        Point2 p;
        const uint32_t pair = 1 + depth * 4 + (k == kPathDimLight ? 0 : 1);
        if (kind_ == Kind::ZSobol)
            zsobol::sample2(z_, pair, p.x, p.y);
        else
            sobol::sample2(i_, n_, seed, key_, pair, p.x, p.y);
        return p;
    }

  private:
    enum class Kind : uint8_t { Uniform, Halton, Sobol, ZSobol, Primary };
    static constexpr uint8_t kPair[kPathDimsPerBounce] = {2, 0, 0, 2, 3, 1, 1, 3};
    static constexpr uint8_t kCoord[kPathDimsPerBounce] = {0, 0, 1, 1, 0, 0, 1, 1};
    static uint32_t pair_of(uint32_t depth, uint32_t k) { return 1 + depth * 4 + kPair[k]; }

    Kind kind_ = Kind::Uniform;
    uint64_t key_ = 0;        // Uniform: the path's key; Halton, Sobol': the pixel's pattern key
    uint64_t prefix_ = 0;     // Uniform: rng::stream_prefix(seed, kPathStream)
    uint32_t i_ = 0, n_ = 0;  // Primary: n_ the path's first number in the vector
    zsobol::Index z_;
    PrimaryVector* primary_ = nullptr;
};

}  // namespace foton
