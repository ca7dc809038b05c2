#pragma once
// A Markov chain's vector of primary samples, mutated lazily (Kelemen et al. 2002, as pbrt-v4's
// MLT sampler does it): a step touches only the numbers its path reads. A number not read for
// a while owes the small steps since its last change; one Gaussian of width sigma sqrt(n) is
// the sum of n of them (wrapping into [0, 1) commutes with the sum), and a number untouched
// since the last accepted large step is that step's fresh value. Every value is a pure function
// of counter-based keys, so a chain is the same whichever thread steps it.
//
// The vector is the chain's state: step() begins a proposal, get() makes its numbers as the
// path asks for them, and accept() or reject() ends it (a rejected step's numbers go back, and
// its iteration does not count towards the small steps owed).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "engine/core/rng.h"

namespace foton {

class PrimaryVector {
  public:
    // A vector of `dims` numbers, all the fresh values of `fresh_key` (a bootstrap sample);
    // `prefix`: rng::stream_prefix of the stream the keys index.
    void reset(uint32_t dims, uint64_t prefix, uint64_t fresh_key, float sigma) {
        coords_.assign(dims, Coord{});
        prefix_ = prefix;
        sigma_ = sigma;
        iteration_ = 1;
        last_large_ = 1;
        large_key_ = fresh_key;
        large_ = false;
        key_ = fresh_key;
        touched_.clear();
    }
    bool large() const { return large_; }

    // Begins a proposal: a large step (every number fresh) or a small one, its numbers keyed
    // by `key`.
    void step(bool large, uint64_t key) {
        ++iteration_;
        large_ = large;
        key_ = key;
        touched_.clear();
    }
    // Number i of the current state (or proposal), made now if the path has not read it yet.
    float get(uint32_t i) {
        if (i >= coords_.size()) return rng::uniform_from(prefix_, key_, 0x10000 + i);
        Coord& c = coords_[i];
        if (c.modified < last_large_) {  // untouched since the last large step: its value
            c.value = fresh(large_key_, i);
            c.modified = last_large_;
        }
        if (c.modified == iteration_) return c.value;
        c.backup = c.value;
        c.backup_modified = c.modified;
        touched_.push_back(i);
        if (large_) {
            c.value = fresh(key_, i);
        } else {
            // The small steps owed since its last change, as one Gaussian (Box-Muller).
            const float n = float(iteration_ - c.modified);
            const float u1 = rng::uniform_from(prefix_, key_, 2 * uint64_t(i) + 0x20000);
            const float u2 = rng::uniform_from(prefix_, key_, 2 * uint64_t(i) + 0x20001);
            const float g =
                std::sqrt(-2.f * std::log(std::max(u1, 1e-30f))) * std::cos(6.2831853f * u2);
            float v = c.value + sigma_ * std::sqrt(n) * g;
            v -= std::floor(v);
            c.value = std::min(v, 0x1.fffffep-1f);
        }
        c.modified = iteration_;
        return c.value;
    }
    // The proposal becomes the state.
    void accept() {
        if (large_) {
            last_large_ = iteration_;
            large_key_ = key_;
        }
    }
    // The state stays: the numbers the proposal changed go back.
    void reject() {
        for (const uint32_t i : touched_) {
            coords_[i].value = coords_[i].backup;
            coords_[i].modified = coords_[i].backup_modified;
        }
        --iteration_;
    }

  private:
    struct Coord {
        float value = 0.f, backup = 0.f;
        uint64_t modified = 0, backup_modified = 0;
    };
    // Dimensions of a key: below 0x10000 the caller's (a step's choice and acceptance), then
    // the numbers past the end, the small steps' Gaussians, and the fresh values.
    float fresh(uint64_t key, uint32_t i) const {
        return rng::uniform_from(prefix_, key, 0x40000 + uint64_t(i));
    }

    std::vector<Coord> coords_;
    std::vector<uint32_t> touched_;
    uint64_t prefix_ = 0, key_ = 0, large_key_ = 0;
    uint64_t iteration_ = 1, last_large_ = 1;
    float sigma_ = 0.01f;
    bool large_ = false;
};

}  // namespace foton
