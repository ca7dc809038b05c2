#pragma once
// Counter-based random numbers: a value is a pure function of (seed, stream, index, dim),
// never the state of a shared generator. This is what makes an image independent of the
// thread count and of the order in which tiles are scheduled.
#include <cstdint>

#include "kernels/counter_hash.h"

namespace foton::rng {

// The hash itself lives with the kernels that draw whole tables of it (kernels/counter_hash.h).
using kern::hash_from;
using kern::mix64;
using kern::stream_prefix;
using kern::to_unit_float;

inline constexpr uint64_t hash(uint64_t seed, uint64_t stream, uint64_t index, uint64_t dim) {
    return hash_from(stream_prefix(seed, stream), index, dim);
}

inline constexpr float uniform(uint64_t seed, uint64_t stream, uint64_t index, uint64_t dim) {
    return to_unit_float(hash(seed, stream, index, dim));
}
inline constexpr float uniform_from(uint64_t prefix, uint64_t index, uint64_t dim) {
    return to_unit_float(hash_from(prefix, index, dim));
}

}  // namespace foton::rng
