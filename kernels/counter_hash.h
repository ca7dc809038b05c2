#pragma once
// Counter-based uniform numbers (engine/core/rng.h builds on these): a number is a pure
// function of (seed, stream, index, dimension), never a generator's state, so an image does
// not depend on the thread count or the order of tiles. uniform_table draws a table of them at
// once, 8 indices per AVX-512 register (64-bit multiplies), for the shading kernels' lanes;
// uniform_table_scalar is its twin, and the two agree bit for bit (the same integer
// arithmetic).
#include <cstddef>
#include <cstdint>

namespace foton::kern {

// SplitMix64 finaliser: a bijective 64-bit mixer with good avalanche.
inline constexpr uint64_t mix64(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

// The part of a number's hash that depends on seed and stream alone.
inline constexpr uint64_t stream_prefix(uint64_t seed, uint64_t stream) {
    return mix64(mix64(seed + 0x9e3779b97f4a7c15ull) ^ (stream + 0x632be59bd9b4e019ull));
}
inline constexpr uint64_t hash_from(uint64_t prefix, uint64_t index, uint64_t dim) {
    return mix64(mix64(prefix ^ (index + 0x85157af5ull * (dim + 1))) ^ dim);
}

// Uniform float in [0, 1) from the top 24 bits.
inline constexpr float to_unit_float(uint64_t bits) {
    return float(bits >> 40) * (1.f / 16777216.f);
}

// out[d * stride + i] = to_unit_float(hash_from(prefix, index[i], dims[d])) for i < n and
// d < n_dims. Indices up to n rounded to 8 are read and written too: the caller pads.
void uniform_table(uint64_t prefix, const uint64_t* index, std::size_t n, const uint64_t* dims,
                   std::size_t n_dims, float* out, std::size_t stride);
void uniform_table_scalar(uint64_t prefix, const uint64_t* index, std::size_t n,
                          const uint64_t* dims, std::size_t n_dims, float* out, std::size_t stride);

}  // namespace foton::kern
