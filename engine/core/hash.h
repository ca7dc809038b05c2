#pragma once
// FNV-1a over bytes: the fingerprint of an image or a file (golden image hashes, the images
// of a scaling study). Not for hash tables or random numbers (core/rng.h).
#include <cstddef>
#include <cstdint>

namespace foton {

// Chains: pass the previous result as `h` to hash several buffers as one.
inline uint64_t fnv1a(const void* data, std::size_t bytes, uint64_t h = 1469598103934665603ull) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
    return h;
}

}  // namespace foton
