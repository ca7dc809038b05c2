#include "halton_net.h"

#include <array>

#include "counter_hash.h"
#include "sobol_net.h"

namespace foton::kern::halton {

namespace {

constexpr std::array<uint32_t, kDims> make_primes() {
    std::array<uint32_t, kDims> p{};
    uint32_t n = 2, k = 0;
    while (k < kDims) {
        bool is_prime = true;
        for (uint32_t d = 2; d * d <= n; ++d)
            if (n % d == 0) is_prime = false;
        if (is_prime) p[k++] = n;
        ++n;
    }
    return p;
}
constexpr std::array<uint32_t, kDims> kPrimes = make_primes();

// Digits are scrambled until their weight drops below float precision (trailing zero digits
// of i too: an unscrambled tail would put every point at the left of its finest interval).
constexpr double kFinest = 1.0 / double(1u << 25);

}  // namespace

uint32_t prime(uint32_t k) {
    return kPrimes[k];
}

float radical_inverse(uint32_t i, uint32_t b) {
    const double inv = 1.0 / b;
    double f = inv, r = 0.0;
    for (; i > 0; i /= b, f *= inv) r += double(i % b) * f;
    return float(r);
}

float scrambled_radical_inverse(uint32_t i, uint32_t b, uint64_t scramble) {
    // Base 2 is the bit-reversed index under the same nested scramble as the Sobol' sampler's.
    if (b == 2) return float(sobol::owen_scramble(sobol::dim0(i), scramble) >> 8) * 0x1p-24f;
    const double inv = 1.0 / b;
    double f = inv, r = 0.0;
    uint64_t prefix = mix64(scramble);
    for (; f > kFinest; f *= inv) {
        uint32_t d = 0;
        if (i > 0) {
            const uint32_t q = i / b;
            d = i - q * b;
            i = q;
        }
        // A permutation of the b digits chosen by the digits above this one: a d + c mod b,
        // a bijection for prime b and a != 0 (a and c by multiply-shift, not division).
        const uint64_t lo = prefix & 0xffffffffu, hi = prefix >> 32;
        const uint32_t a = 1 + uint32_t((lo * (b - 1)) >> 32);
        const uint32_t c = uint32_t((hi * b) >> 32);
        r += double(d == 0 ? c : (a * d + c) % b) * f;
        prefix = mix64(prefix ^ (d + 0x9e3779b97f4a7c15ull));
    }
    // Below 1 even where every scrambled digit is b - 1.
    return float(r < 1.0 ? r : 0x1.fffffep-1);
}

float sample(uint32_t i, uint64_t seed, uint64_t key, uint32_t dim) {
    if (dim >= kDims)
        return to_unit_float(hash_from(stream_prefix(seed, key), i, 0x4a10000ull + dim));
    return scrambled_radical_inverse(i, kPrimes[dim],
                                     hash_from(stream_prefix(seed, key), dim, 0x4a19));
}

void sample_table_scalar(uint64_t seed, const uint32_t* index, const uint64_t* key, std::size_t n,
                         const uint32_t* dims, std::size_t n_dims, float* out, std::size_t stride) {
    for (std::size_t d = 0; d < n_dims; ++d)
        for (std::size_t s = 0; s < n; ++s)
            out[d * stride + s] = sample(index[s], seed, key[s], dims[d]);
}

}  // namespace foton::kern::halton
