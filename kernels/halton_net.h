#pragma once
// Randomised Halton points (the engine names them foton::halton, engine/core/halton.h): the sampler
// that `sampler="halton"` selects. Dimension k of point i is the radical inverse of i in the k-th
// prime base, with every digit scrambled by a nested random linear permutation (d -> a d + c mod b,
// keyed by the digits above it, as Owen scrambling is in base 2), keyed by (seed, pixel, pass,
// dimension). A pixel's n samples of a pass are points 0..n-1: the first two dimensions (bases 2
// and 3) stratify the pixel, and a path's dimensions follow in bases 5, 7, 11, ... Scrambling keeps
// every elementary interval's count in its own base, removes the correlation between large bases
// that plain Halton shows, and makes each pixel's set an independent randomisation. Past kDims
// dimensions (very deep paths) the numbers are counter-based random ones.
#include <cstddef>
#include <cstdint>

namespace foton::kern::halton {

inline constexpr uint32_t kDims = 128;

// The k-th prime (k < kDims): 2, 3, 5, ...
uint32_t prime(uint32_t k);
// The plain radical inverse of i in base b (no scrambling).
float radical_inverse(uint32_t i, uint32_t b);
// The scrambled radical inverse of i in base b, keyed by `scramble`.
float scrambled_radical_inverse(uint32_t i, uint32_t b, uint64_t scramble);
// Dimension `dim` of point i of the set keyed by (seed, key).
float sample(uint32_t i, uint64_t seed, uint64_t key, uint32_t dim);

// The table of dimensions `dims` (each < kDims) of n points (point s is index[s] of the set
// keyed by (seed, key[s])): row d of `out` (column s, rows `stride` apart) is what sample()
// gives one at a time, bit for bit. sample_table runs 8 points per AVX-512 register: the
// digits by exact double-precision division, each digit's permutation from the 64-bit hash
// of the digits above it, the sum in doubles in the twin's order; base 2 is the Owen-scrambled
// bit reversal of the Sobol' kernel. sample_table_scalar is its twin, sample() in a loop.
// Points up to n rounded to 8 are read and written: the caller pads.
void sample_table(uint64_t seed, const uint32_t* index, const uint64_t* key, std::size_t n,
                  const uint32_t* dims, std::size_t n_dims, float* out, std::size_t stride);
void sample_table_scalar(uint64_t seed, const uint32_t* index, const uint64_t* key, std::size_t n,
                         const uint32_t* dims, std::size_t n_dims, float* out, std::size_t stride);

}  // namespace foton::kern::halton
