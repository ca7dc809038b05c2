#pragma once
// Owen-scrambled Sobol' points, padded: the sampler that `sampler="sobol"` selects. A pixel's
// n samples of a pass are the first n points of the (0, 2)-sequence formed by Sobol's first two
// dimensions, for every pair of dimensions a path uses; each pair gets its own nested uniform
// (Owen) scramble and its own permutation of the n points, both keyed by (seed, pixel, pass,
// pair), so pairs are stratified on their own and uncorrelated with one another (pbrt-v4's
// padded Sobol' sampler in spirit; our own code). Everything is a pure function of its keys:
// images do not depend on the thread count.
#include <cstddef>
#include <cstdint>

#include "counter_hash.h"

namespace foton::kern::sobol {

// Sobol's first two dimensions at index i, as 32-bit fractions: the bit-reversed index and
// the second dimension's generator matrix (the Pascal matrix mod 2) applied to it.
uint32_t dim0(uint32_t i);
uint32_t dim1(uint32_t i);

// A nested uniform scramble of a 32-bit fraction: bit b is flipped by a hash of the bits
// above it and `seed`. A bijection that keeps every elementary interval's point count.
uint32_t owen_scramble(uint32_t v, uint64_t seed);

// A random permutation of [0, n), element i, keyed by `seed` (cycle walking over bijections
// of the next power of two).
uint32_t permute(uint32_t i, uint32_t n, uint64_t seed);

// Point i of an n-point scrambled (0, 2)-net in [0, 1)^2 keyed by `key`, for pair `pair`
// (pairs are permuted and scrambled independently): (x, y).
void sample2(uint32_t i, uint32_t n, uint64_t seed, uint64_t key, uint32_t pair, float& x,
             float& y);
// One coordinate (0 or 1) of the same point.
float sample1(uint32_t i, uint32_t n, uint64_t seed, uint64_t key, uint32_t pair, int coord);

// The pieces sample2 is made of, for the table kernel: the key of a sample's pair (a hash of
// its pattern key and the pair's salt), and the second dimension's lookup tables (4 x 256
// entries: the generator matrix applied to each byte of an index).
inline uint64_t pair_salt(uint64_t seed, uint32_t pair) {
    return mix64(seed + 0x50b0u * (uint64_t(pair) + 1));
}
uint64_t pair_key(uint64_t seed, uint64_t key, uint32_t pair);
const uint32_t* dim1_tables();

// A table of points for many samples at once: for each of the `n_pairs` pairs and each of
// the n samples (index[s] of count[s] points, keyed by key[s]), x in row 2 p and y in row
// 2 p + 1 of `out` (column s, rows `stride` apart): what sample2 gives one at a time, bit
// for bit. sample_table runs 16 samples per AVX-512 register (the 64-bit hashes 8 at a
// time); sample_table_scalar is its twin, sample2 in a loop. Samples up to n rounded to 16
// are read and written: the caller pads.
void sample_table(uint64_t seed, const uint32_t* index, const uint32_t* count, const uint64_t* key,
                  std::size_t n, const uint32_t* pairs, std::size_t n_pairs, float* out,
                  std::size_t stride);
void sample_table_scalar(uint64_t seed, const uint32_t* index, const uint32_t* count,
                         const uint64_t* key, std::size_t n, const uint32_t* pairs,
                         std::size_t n_pairs, float* out, std::size_t stride);

}  // namespace foton::kern::sobol
