#pragma once
// Randomised Halton points: the sampler that `sampler="halton"` selects. Dimension k of point
// i is the radical inverse of i in the k-th prime base, with every digit scrambled by a
// nested random linear permutation (d -> a d + c mod b, keyed by the digits above it, as
// Owen scrambling is in base 2), keyed by (seed, pixel, pass, dimension). A pixel's n samples
// of a pass are points 0..n-1: the first two dimensions (bases 2 and 3) stratify the pixel,
// and a path's dimensions follow in bases 5, 7, 11, ... Scrambling keeps every elementary
// interval's count in its own base, removes the correlation between large bases that plain
// Halton shows, and makes each pixel's set an independent randomisation. Past kDims
// dimensions (very deep paths) the numbers are counter-based random ones.
#include <cstdint>

namespace foton::halton {

inline constexpr uint32_t kDims = 128;

// The k-th prime (k < kDims): 2, 3, 5, ...
uint32_t prime(uint32_t k);
// The plain radical inverse of i in base b (no scrambling).
float radical_inverse(uint32_t i, uint32_t b);
// The scrambled radical inverse of i in base b, keyed by `scramble`.
float scrambled_radical_inverse(uint32_t i, uint32_t b, uint64_t scramble);
// Dimension `dim` of point i of the set keyed by (seed, key).
float sample(uint32_t i, uint64_t seed, uint64_t key, uint32_t dim);

}  // namespace foton::halton
