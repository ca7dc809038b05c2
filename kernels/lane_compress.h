#pragma once
// Packing a chunk's valid lanes into a batch (the shading kernels' read-back, issue 35): the
// lanes whose flag is not 0, of several 32-bit columns at once, written one after another in
// lane order. compress_lanes uses AVX-512's compress stores (16 lanes an instruction) where
// the build has them; compress_lanes_scalar is its twin, a loop.
#include <cstddef>
#include <cstdint>

namespace foton::kern {

// For every column c < columns: src[c][k] for the lanes k < n whose valid[k] != 0, stored at
// dst[c][0], dst[c][1], ... (32-bit words, floats or integers alike, copied bit for bit).
// Returns how many lanes were valid.
std::size_t compress_lanes(const float* valid, std::size_t n, const uint32_t* const* src,
                           uint32_t* const* dst, std::size_t columns);
std::size_t compress_lanes_scalar(const float* valid, std::size_t n, const uint32_t* const* src,
                                  uint32_t* const* dst, std::size_t columns);

}  // namespace foton::kern
