#include "zsobol_net.h"

#include <bit>

#include "counter_hash.h"
#include "sobol_net.h"

namespace foton::kern::zsobol {

namespace {

// The 24 permutations of {0, 1, 2, 3}, two bits per entry (entry d at bits 2d, 2d + 1).
constexpr auto kPermutations = [] {
    struct Table {
        uint8_t p[24] = {};
    } t;
    int k = 0;
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b)
            for (int c = 0; c < 4; ++c) {
                const int d = 6 - a - b - c;
                if (a == b || a == c || b == c || d < 0 || d > 3 || d == a || d == b || d == c)
                    continue;
                t.p[k++] = uint8_t(a | (b << 2) | (c << 4) | (d << 6));
            }
    return t;
}();
static_assert(kPermutations.p[23] != 0, "all 24 permutations of four digits");

uint32_t ceil_log2(uint32_t n) {
    return n <= 1 ? 0u : uint32_t(std::bit_width(n - 1));
}

float to_float(uint32_t v) {
    return float(v >> 8) * (1.f / 16777216.f);
}

}  // namespace

uint64_t pair_key(uint64_t key, uint32_t pair) {
    return mix64(key + 0x2505u * (uint64_t(pair) + 1));
}

const uint32_t* permutations() {
    static const auto table = [] {
        struct Wide {
            uint32_t p[24];
        } w{};
        for (int k = 0; k < 24; ++k) w.p[k] = kPermutations.p[k];
        return w;
    }();
    return table.p;
}

uint64_t morton2(uint32_t x, uint32_t y) {
    auto spread = [](uint64_t v) {
        v &= 0xffffffffull;
        v = (v | (v << 16)) & 0x0000ffff0000ffffull;
        v = (v | (v << 8)) & 0x00ff00ff00ff00ffull;
        v = (v | (v << 4)) & 0x0f0f0f0f0f0f0f0full;
        v = (v | (v << 2)) & 0x3333333333333333ull;
        return (v | (v << 1)) & 0x5555555555555555ull;
    };
    return spread(x) | (spread(y) << 1);
}

namespace {
// The key of a pass: every sample of it has the same, so each thread keeps the last one (four
// 64-bit mixes that were a third of index_of's time).
uint64_t pass_key(uint64_t seed, uint64_t pass) {
    thread_local bool valid = false;
    thread_local uint64_t last_seed = 0, last_pass = 0, last_key = 0;
    if (!valid || seed != last_seed || pass != last_pass) {
        last_key = hash_from(stream_prefix(seed, 0x7a50b01u), pass, 0);
        last_seed = seed;
        last_pass = pass;
        valid = true;
    }
    return last_key;
}
}  // namespace

Index index_of(uint32_t x, uint32_t y, uint32_t width, uint32_t height, uint32_t i, uint32_t n,
               uint64_t seed, uint64_t pass) {
    const uint32_t side = ceil_log2(width > height ? width : height);
    const uint32_t log2n = ceil_log2(n);
    Index s;
    s.index = (morton2(x, y) << log2n) | i;
    s.bits = 2 * side + log2n;
    s.key = pass_key(seed, pass);
    return s;
}

namespace {

// The index's digits permuted, for the pair keyed by `pk`: the permutation of each digit
// chosen by a hash of the digits above it (digit_permutation, zsobol_net.h). The loop's
// iterations are independent, so they overlap in the pipeline.
uint64_t permute_digits(const Index& s, uint64_t pk) {
    const uint32_t pk32 = fold32(pk);
    uint64_t out = 0;
    // With an odd bit count the lowest bit stands alone: a base-2 digit, flipped or not.
    const uint32_t lone = s.bits & 1u;
    for (int shift = int(s.bits) - 2; shift >= int(lone); shift -= 2) {
        const uint32_t perm =
            kPermutations.p[digit_permutation(fold32(s.index >> (shift + 2)), pk32, shift)];
        const uint32_t digit = uint32_t(s.index >> shift) & 3u;
        out |= uint64_t((perm >> (2 * digit)) & 3u) << shift;
    }
    if (lone) out |= (s.index & 1u) ^ lone_flip(fold32(s.index >> 1), pk32);
    return out;
}

// The pair's permuted index and its Owen scramble key.
uint64_t scrambled(const Index& s, uint32_t pair, uint64_t& key) {
    const uint64_t pk = pair_key(s.key, pair);
    const uint64_t j = permute_digits(s, pk);
    key = j >> 32 ? mix64(pk ^ (j >> 32)) : pk;
    return j;
}

}  // namespace

uint64_t permuted_index(const Index& s, uint32_t pair) {
    return permute_digits(s, pair_key(s.key, pair));
}

void sample2(const Index& s, uint32_t pair, float& x, float& y) {
    uint64_t k;
    const uint32_t j = uint32_t(scrambled(s, pair, k));
    x = to_float(sobol::owen_scramble(sobol::dim0(j), k + 1));
    y = to_float(sobol::owen_scramble(sobol::dim1(j), k + 2));
}

float sample1(const Index& s, uint32_t pair, int coord) {
    uint64_t k;
    const uint32_t j = uint32_t(scrambled(s, pair, k));
    return coord == 0 ? to_float(sobol::owen_scramble(sobol::dim0(j), k + 1))
                      : to_float(sobol::owen_scramble(sobol::dim1(j), k + 2));
}

void sample_table_scalar(const uint64_t* index, const uint32_t* bits, const uint64_t* key,
                         std::size_t n, const uint32_t* pairs, std::size_t n_pairs, float* out,
                         std::size_t stride) {
    for (std::size_t p = 0; p < n_pairs; ++p)
        for (std::size_t s = 0; s < n; ++s)
            sample2(Index{index[s], bits[s], key[s]}, pairs[p], out[2 * p * stride + s],
                    out[(2 * p + 1) * stride + s]);
}

}  // namespace foton::kern::zsobol
