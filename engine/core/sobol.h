#pragma once
// Owen-scrambled Sobol' points, padded: the sampler that `sampler="sobol"` selects. A pixel's
// n samples of a pass are the first n points of the (0, 2)-sequence formed by Sobol's first two
// dimensions, for every pair of dimensions a path uses; each pair gets its own nested uniform
// (Owen) scramble and its own permutation of the n points, both keyed by (seed, pixel, pass,
// pair), so pairs are stratified on their own and uncorrelated with one another (pbrt-v4's
// padded Sobol' sampler in spirit; our own code). Everything is a pure function of its keys:
// images do not depend on the thread count.
#include <cstdint>

namespace foton::sobol {

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

}  // namespace foton::sobol
