#pragma once
// Counter-based random numbers: a value is a pure function of (seed, stream, index, dim),
// never the state of a shared generator. This is what makes an image independent of the
// thread count and of the order in which tiles are scheduled.
#include <cstdint>

namespace foton::rng {

// SplitMix64 finaliser: a bijective 64-bit mixer with good avalanche.
inline constexpr uint64_t mix64(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

// The part of hash() that depends on seed and stream alone: a caller drawing many numbers of
// one stream computes it once (half the multiplies of each number) and gets the same bits.
inline constexpr uint64_t stream_prefix(uint64_t seed, uint64_t stream) {
    return mix64(mix64(seed + 0x9e3779b97f4a7c15ull) ^ (stream + 0x632be59bd9b4e019ull));
}
inline constexpr uint64_t hash_from(uint64_t prefix, uint64_t index, uint64_t dim) {
    return mix64(mix64(prefix ^ (index + 0x85157af5ull * (dim + 1))) ^ dim);
}

inline constexpr uint64_t hash(uint64_t seed, uint64_t stream, uint64_t index, uint64_t dim) {
    return hash_from(stream_prefix(seed, stream), index, dim);
}

// Uniform float in [0, 1) from the top 24 bits.
inline constexpr float to_unit_float(uint64_t bits) {
    return float(bits >> 40) * (1.f / 16777216.f);
}

inline constexpr float uniform(uint64_t seed, uint64_t stream, uint64_t index, uint64_t dim) {
    return to_unit_float(hash(seed, stream, index, dim));
}
inline constexpr float uniform_from(uint64_t prefix, uint64_t index, uint64_t dim) {
    return to_unit_float(hash_from(prefix, index, dim));
}

}  // namespace foton::rng
