#pragma once
// Sobol' points in Z-order over the image: the sampler that `sampler="zsobol"` selects. Every
// pixel sample of a pass is one index of a single image-wide (0, 2)-sequence: the index is the
// pixel's Morton code (in the full image, so a crop draws the samples of the whole render)
// followed by the sample's number in the pixel. Each aligned block of 2^k indices of a
// (0, 2)-sequence is a (0, k, 2)-net, so the samples of one pixel are stratified, and so are
// the samples of every 2x2, 4x4, ... block of pixels together: neighbouring pixels cover each
// other's gaps and their errors cancel, which pushes the image's error towards high
// frequencies (blue noise). The idea is Ahmed and Wonka's hierarchical pixel ordering (2020),
// as pbrt-v4's ZSobolSampler uses it; this is our own code.
//
// Each dimension pair (pair 0 the film position, then a path's pairs) reorders the index by
// permuting its base-4 digits, each digit by one of the 24 permutations of {0, 1, 2, 3}
// chosen by a hash of the digits above it: a bijection that maps aligned blocks to aligned
// blocks, so the nets survive while the pairs of one sample are decorrelated. The points are
// then Owen-scrambled (sobol::owen_scramble) per pair. Indices longer than 32 bits (huge
// images at many samples) keep their low 32 bits for the 32-bit generator matrices; the bits
// above key the scramble, so each 2^32 block is its own randomisation.
#include <cstddef>
#include <cstdint>

namespace foton::kern::zsobol {

// One pixel sample's place in the sequence.
struct Index {
    uint64_t index = 0;  // (Morton(x, y) << log2 n) | i
    uint32_t bits = 0;   // significant bits of `index`
    uint64_t key = 0;    // (seed, pass): every pass is its own randomisation
};

// Interleaves the bits of x (even positions) and y (odd positions).
uint64_t morton2(uint32_t x, uint32_t y);

// Sample i of n (n is rounded up to a power of two for the layout) of the pixel at (x, y)
// of a full image of width x height, in pass `pass`.
Index index_of(uint32_t x, uint32_t y, uint32_t width, uint32_t height, uint32_t i, uint32_t n,
               uint64_t seed, uint64_t pass);

// The index as pair `pair` sees it: its base-4 digits permuted (a lone lowest bit is flipped
// by a hash instead). Exposed for the tests.
uint64_t permuted_index(const Index& s, uint32_t pair);

// Pair `pair` of the sample: (x, y) in [0, 1)^2, and one coordinate of it.
void sample2(const Index& s, uint32_t pair, float& x, float& y);
float sample1(const Index& s, uint32_t pair, int coord);

// The table of pairs `pairs` for n samples (sample s is {index[s], bits[s], key[s]}): x in row
// 2 p and y in row 2 p + 1 of `out` (column s, rows `stride` apart), what sample2 gives one at
// a time, bit for bit. sample_table runs 16 samples per AVX-512 register where they share a
// key (one render pass) and their indices fit in 32 bits (a digit mask per lane where their
// lengths differ), the Owen scramble's hashes then computed once for all; other groups of 16
// take sample_table_scalar, its twin, which is sample2 in a loop. Samples up to n rounded to
// 16 are read and written: the caller pads.
void sample_table(const uint64_t* index, const uint32_t* bits, const uint64_t* key, std::size_t n,
                  const uint32_t* pairs, std::size_t n_pairs, float* out, std::size_t stride);
void sample_table_scalar(const uint64_t* index, const uint32_t* bits, const uint64_t* key,
                         std::size_t n, const uint32_t* pairs, std::size_t n_pairs, float* out,
                         std::size_t stride);
// The pieces for the table kernel: the pair's key, and the 24 permutations of {0, 1, 2, 3}
// (entry d of permutation k at bits 2d, 2d + 1 of permutations()[k]).
uint64_t pair_key(uint64_t key, uint32_t pair);
const uint32_t* permutations();

// The hashes of the digit permutation, in 32-bit arithmetic so that the kernel runs 16 lanes
// per AVX-512 register: a 64-bit value folded to 32 bits, which of the 24 permutations the
// digit at `shift` takes given the digits above it (`above`, folded) and the pair's folded
// key, and whether a lone lowest bit is flipped. Two multiply-xorshift rounds; the choice
// comes from the hash's top 24 bits.
inline uint32_t fold32(uint64_t v) {
    return uint32_t(v) ^ uint32_t(v >> 32);
}
inline uint32_t digit_permutation(uint32_t above, uint32_t pk32, int shift) {
    uint32_t h = (above ^ (pk32 + uint32_t(shift) * 0x9e3779b9u)) * 0x85ebca6bu;
    h ^= h >> 15;
    h *= 0xc2b2ae35u;
    h ^= h >> 13;
    return ((h >> 8) * 24u) >> 24;
}
inline uint32_t lone_flip(uint32_t above, uint32_t pk32) {
    uint32_t h = (above ^ pk32) * 0x94d049bbu;
    h ^= h >> 15;
    h *= 0x846ca68bu;
    return h >> 31;
}

}  // namespace foton::kern::zsobol
