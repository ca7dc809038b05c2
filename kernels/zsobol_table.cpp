// zsobol::sample_table: sixteen samples at a time, in 32-bit lanes. A render pass's samples
// share one key, so the pair's key and the Owen scramble's hashes are computed once per pair
// and broadcast; the digit permutation runs one base-4 digit per step from the top, its
// hash in 32-bit arithmetic (zsobol_net.h), the permutation taken from a two-register table
// by one permute. A group whose keys differ, or whose indices pass 32 bits, runs the scalar
// twin. Builds without AVX-512 (F, DQ, CD, VL) run the twin throughout.
#include <algorithm>

#include "counter_hash.h"
#include "sobol_simd.h"
#include "zsobol_net.h"

namespace foton::kern::zsobol {

#if FOTON_SOBOL_SIMD
namespace {

constexpr std::size_t kGroup = 16;
constexpr __mmask16 kAll = 0xffff;

inline __m512i set32(uint32_t v) {
    return _mm512_set1_epi32(int32_t(v));
}
inline __m512i shr32(__m512i z, unsigned n) {
    return _mm512_maskz_srli_epi32(kAll, z, n);
}
inline __m512i shl32(__m512i z, unsigned n) {
    return _mm512_maskz_slli_epi32(kAll, z, n);
}
inline __m512i mul32(__m512i a, __m512i b) {
    return _mm512_mullo_epi32(a, b);
}

// digit_permutation's hash for 16 lanes of `above` (the loop constant c = pk32 + shift * k).
inline __m512i permutation_index(__m512i above, uint32_t c) {
    __m512i h = mul32(_mm512_xor_si512(above, set32(c)), set32(0x85ebca6bu));
    h = _mm512_xor_si512(h, shr32(h, 15));
    h = mul32(h, set32(0xc2b2ae35u));
    h = _mm512_xor_si512(h, shr32(h, 13));
    return shr32(mul32(shr32(h, 8), set32(24u)), 24);
}

inline __m512i bit_reverse(__m512i i) {
    auto swap = [](__m512i x, unsigned s, uint32_t m) {
        const __m512i mask = set32(m);
        return _mm512_or_si512(shl32(_mm512_and_si512(x, mask), s),
                               _mm512_and_si512(shr32(x, s), mask));
    };
    i = _mm512_or_si512(shl32(i, 16), shr32(i, 16));
    i = swap(i, 8, 0x00ff00ffu);
    i = swap(i, 4, 0x0f0f0f0fu);
    i = swap(i, 2, 0x33333333u);
    return swap(i, 1, 0x55555555u);
}

// The second dimension's generator matrix times the index, nibble by nibble: eight lookups in
// 16-entry tables held in registers (one permute each), not four gathers from the byte
// tables (the product is linear, so nibble n's table is the byte table's entries for it).
struct Dim1Nibbles {
    __m512i t[8];
};
const Dim1Nibbles& dim1_nibbles() {
    static const Dim1Nibbles d = [] {
        Dim1Nibbles out;
        const uint32_t* bytes = sobol::dim1_tables();
        for (uint32_t n = 0; n < 8; ++n) {
            alignas(64) uint32_t w[16];
            for (uint32_t v = 0; v < 16; ++v) w[v] = bytes[(n / 2) * 256 + (n % 2 ? v << 4 : v)];
            out.t[n] = _mm512_load_si512(w);
        }
        return out;
    }();
    return d;
}

inline __m512i dim1_lanes(__m512i i, const Dim1Nibbles& nib) {
    const __m512i nibble = set32(15);
    __m512i out = _mm512_maskz_permutexvar_epi32(kAll, _mm512_and_si512(i, nibble), nib.t[0]);
    for (unsigned n = 1; n < 8; ++n)
        out = _mm512_xor_si512(out, _mm512_maskz_permutexvar_epi32(
                                        kAll, _mm512_and_si512(shr32(i, 4 * n), nibble), nib.t[n]));
    return out;
}

// owen_scramble(v, seed) for 16 values whose bit reversal x is given, with one seed.
inline __m512i owen_reversed(__m512i x, uint64_t seed) {
    const uint64_t h = mix64(seed), h2 = mix64(seed ^ 0x632be59bd9b4e019ull);
    x = _mm512_add_epi32(x, set32(uint32_t(h)));
    x = mul32(x, set32(uint32_t(h >> 32) | 1u));
    x = _mm512_xor_si512(x, mul32(x, set32(uint32_t(h2) << 1)));
    x = _mm512_add_epi32(x, set32(uint32_t(h2 >> 32)));
    x = _mm512_xor_si512(x, mul32(x, set32(0x7a6b5c4eu)));
    return bit_reverse(x);
}

inline __m512 unit_float(__m512i v) {
    return _mm512_mul_ps(_mm512_maskz_cvtepi32_ps(kAll, shr32(v, 8)),
                         _mm512_set1_ps(1.f / 16777216.f));
}

// The 24 permutations (one byte each, in 32-bit entries) as two 16-entry tables.
struct PermutationTables {
    __m512i lo, hi;
};
const PermutationTables& permutation_tables() {
    static const PermutationTables t = [] {
        alignas(64) uint32_t w[32] = {};
        for (int k = 0; k < 24; ++k) w[k] = permutations()[k];
        return PermutationTables{_mm512_load_si512(w), _mm512_load_si512(w + 16)};
    }();
    return t;
}

// permute_digits for 16 indices (32-bit lanes, `bits` each) of the pair with folded key pk32.
__m512i permute_lanes(__m512i index, __m512i bits, uint32_t max_bits, bool one_length,
                      uint32_t pk32) {
    const PermutationTables& table = permutation_tables();
    const __m512i three = set32(3), one = set32(1);
    const __m512i lone = _mm512_and_si512(bits, one);
    __m512i out = _mm512_setzero_si512();
    // One length (the usual case: one image, one sample count): digits at every other
    // position, no mask. Else every position, each lane where it has a digit.
    const int step = one_length ? 2 : 1;
    const int lowest = one_length ? int(max_bits & 1u) : 0;
    for (int shift = int(max_bits) - 2; shift >= lowest; shift -= step) {
        __mmask16 active = kAll;
        if (!one_length)
            active = _mm512_cmpge_epu32_mask(bits, set32(uint32_t(shift) + 2)) &
                     _mm512_cmpeq_epi32_mask(lone, set32(uint32_t(shift) & 1u));
        if (!active) continue;
        const __m512i which = permutation_index(shr32(index, unsigned(shift) + 2),
                                                pk32 + uint32_t(shift) * 0x9e3779b9u);
        const __m512i perm = _mm512_permutex2var_epi32(table.lo, which, table.hi);
        const __m512i digit = _mm512_and_si512(shr32(index, unsigned(shift)), three);
        const __m512i moved = _mm512_and_si512(
            _mm512_maskz_srlv_epi32(kAll, perm, _mm512_add_epi32(digit, digit)), three);
        out = _mm512_mask_or_epi32(out, active, out, shl32(moved, unsigned(shift)));
    }
    // A lone lowest bit, flipped by a hash.
    __m512i h = mul32(_mm512_xor_si512(shr32(index, 1), set32(pk32)), set32(0x94d049bbu));
    h = _mm512_xor_si512(h, shr32(h, 15));
    h = mul32(h, set32(0x846ca68bu));
    const __m512i flip = _mm512_xor_si512(_mm512_and_si512(index, one), shr32(h, 31));
    return _mm512_mask_or_epi32(out, _mm512_test_epi32_mask(lone, lone), out, flip);
}

// Sixteen 64-bit values narrowed to 32-bit lanes.
inline __m512i load_low32(const uint64_t* v) {
    const __m256i a = _mm512_maskz_cvtepi64_epi32(__mmask8(0xff), _mm512_loadu_si512(v));
    const __m256i b = _mm512_maskz_cvtepi64_epi32(__mmask8(0xff), _mm512_loadu_si512(v + 8));
    const __m512i wide = _mm512_castsi256_si512(a);
    return _mm512_mask_inserti64x4(wide, __mmask8(0xff), wide, b, 1);
}

}  // namespace

void sample_table(const uint64_t* index, const uint32_t* bits, const uint64_t* key, std::size_t n,
                  const uint32_t* pairs, std::size_t n_pairs, float* out, std::size_t stride) {
    for (std::size_t s = 0; s < n; s += kGroup) {
        const uint32_t max_bits = *std::max_element(bits + s, bits + s + kGroup);
        const bool one_key =
            std::all_of(key + s, key + s + kGroup, [&](uint64_t k) { return k == key[s]; });
        if (max_bits > 32 || !one_key) {
            sample_table_scalar(index + s, bits + s, key + s, kGroup, pairs, n_pairs, out + s,
                                stride);
            continue;
        }
        const bool one_length =
            std::all_of(bits + s, bits + s + kGroup, [&](uint32_t b) { return b == max_bits; });
        const __m512i idx = load_low32(index + s);
        const Dim1Nibbles& nibbles = dim1_nibbles();
        const __m512i nbits = _mm512_loadu_si512(bits + s);
        for (std::size_t p = 0; p < n_pairs; ++p) {
            // Indices of 32 bits or fewer: the scramble's key is the pair's (scrambled() in
            // zsobol_net.cpp).
            const uint64_t pk = pair_key(key[s], pairs[p]);
            const __m512i j = permute_lanes(idx, nbits, max_bits, one_length, fold32(pk));
            const __m512i x = owen_reversed(j, pk + 1);
            const __m512i y = owen_reversed(bit_reverse(dim1_lanes(j, nibbles)), pk + 2);
            _mm512_storeu_ps(out + 2 * p * stride + s, unit_float(x));
            _mm512_storeu_ps(out + (2 * p + 1) * stride + s, unit_float(y));
        }
    }
}
#else
void sample_table(const uint64_t* index, const uint32_t* bits, const uint64_t* key, std::size_t n,
                  const uint32_t* pairs, std::size_t n_pairs, float* out, std::size_t stride) {
    sample_table_scalar(index, bits, key, (n + 15) / 16 * 16, pairs, n_pairs, out, stride);
}
#endif

}  // namespace foton::kern::zsobol
