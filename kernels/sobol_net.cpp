#include "sobol_net.h"

#include <algorithm>
#include <bit>

#include "counter_hash.h"

namespace foton::kern::sobol {

uint32_t dim0(uint32_t i) {
    i = (i << 16) | (i >> 16);
    i = ((i & 0x00ff00ffu) << 8) | ((i & 0xff00ff00u) >> 8);
    i = ((i & 0x0f0f0f0fu) << 4) | ((i & 0xf0f0f0f0u) >> 4);
    i = ((i & 0x33333333u) << 2) | ((i & 0xccccccccu) >> 2);
    return ((i & 0x55555555u) << 1) | ((i & 0xaaaaaaaau) >> 1);
}

namespace {
// Column k of the second dimension's generator matrix: v_0 = 1 << 31, v_k = v_{k-1} ^
// (v_{k-1} >> 1). The product with an index is the xor of the columns of its set bits; the
// tables hold those xors for each byte of the index, so a long index (zsobol's, 20-30 bits)
// costs four lookups instead of a loop over its bits.
struct Dim1Tables {
    uint32_t t[4][256] = {};
};
constexpr Dim1Tables make_dim1_tables() {
    Dim1Tables d;
    uint32_t column[32] = {};
    uint32_t v = 1u << 31;
    for (int k = 0; k < 32; ++k, v ^= v >> 1) column[k] = v;
    for (int b = 0; b < 4; ++b)
        for (uint32_t x = 0; x < 256; ++x) {
            uint32_t out = 0;
            for (int k = 0; k < 8; ++k)
                if (x >> k & 1u) out ^= column[8 * b + k];
            d.t[b][x] = out;
        }
    return d;
}
constexpr Dim1Tables kDim1 = make_dim1_tables();
}  // namespace

const uint32_t* dim1_tables() {
    return &kDim1.t[0][0];
}

uint32_t dim1(uint32_t i) {
    return kDim1.t[0][i & 0xffu] ^ kDim1.t[1][(i >> 8) & 0xffu] ^ kDim1.t[2][(i >> 16) & 0xffu] ^
           kDim1.t[3][i >> 24];
}

uint32_t owen_scramble(uint32_t v, uint64_t seed) {
    // In bit-reversed order a nested scramble flips each bit by a function of the bits below
    // it; adding, multiplying by an odd number and xoring in a product with an even number
    // all do exactly that (carries only move up), so their composition, keyed by the seed,
    // is a nested scramble and a bijection, for a few operations per value.
    uint32_t x = dim0(v);  // bit reversal
    const uint64_t h = mix64(seed), h2 = mix64(seed ^ 0x632be59bd9b4e019ull);
    x += uint32_t(h);
    x *= uint32_t(h >> 32) | 1u;
    x ^= x * (uint32_t(h2) << 1);
    x += uint32_t(h2 >> 32);
    x ^= x * 0x7a6b5c4eu;
    return dim0(x);
}

uint32_t permute(uint32_t i, uint32_t n, uint64_t seed) {
    if (n <= 1) return 0;
    uint32_t mask = n - 1;
    for (int s = 1; s < 32; s <<= 1) mask |= mask >> s;
    const uint64_t h = mix64(seed);
    const uint32_t a = uint32_t(h) | 1u, c = uint32_t(h >> 32), a2 = uint32_t(h >> 16) | 1u;
    const int shift = std::max(1, std::countr_one(mask) / 2);
    // Each step is a bijection of [0, mask]: odd multiplication, addition, xor-shift right.
    // Values past n walk on until they fall inside (the walk follows a permutation cycle).
    do {
        i = (i * a + c) & mask;
        i ^= i >> shift;
        i = (i * a2) & mask;
        i ^= i >> 1;
    } while (i >= n);
    return i;
}

uint64_t pair_key(uint64_t seed, uint64_t key, uint32_t pair) {
    return mix64(key ^ pair_salt(seed, pair));
}

namespace {
// 24 bits: the float stays below 1.
float to_float(uint32_t v) {
    return float(v >> 8) * (1.f / 16777216.f);
}
}  // namespace

void sample2(uint32_t i, uint32_t n, uint64_t seed, uint64_t key, uint32_t pair, float& x,
             float& y) {
    const uint64_t k = pair_key(seed, key, pair);
    const uint32_t j = permute(i, n, k);
    x = to_float(owen_scramble(dim0(j), k + 1));
    y = to_float(owen_scramble(dim1(j), k + 2));
}

float sample1(uint32_t i, uint32_t n, uint64_t seed, uint64_t key, uint32_t pair, int coord) {
    const uint64_t k = pair_key(seed, key, pair);
    const uint32_t j = permute(i, n, k);
    return coord == 0 ? to_float(owen_scramble(dim0(j), k + 1))
                      : to_float(owen_scramble(dim1(j), k + 2));
}

void sample_table_scalar(uint64_t seed, const uint32_t* index, const uint32_t* count,
                         const uint64_t* key, std::size_t n, const uint32_t* pairs,
                         std::size_t n_pairs, float* out, std::size_t stride) {
    for (std::size_t p = 0; p < n_pairs; ++p)
        for (std::size_t s = 0; s < n; ++s)
            sample2(index[s], count[s], seed, key[s], pairs[p], out[2 * p * stride + s],
                    out[(2 * p + 1) * stride + s]);
}

}  // namespace foton::kern::sobol
