#pragma once
// The points of one contiguous run of SoA coordinates that lie within a radius of a query
// point: the merge grid's bucket scan (engine/transport/bidir/vertex_grid.h), W points a
// step. The grid stores its vertices' coordinates in bucket order, so a bucket is one run of
// sequential loads instead of an index chase per vertex.
//
// radius_scan is the SIMD kernel, radius_scan_scalar its twin; both compute the squared
// distance as ((dx dx + dy dy) + dz dz) and visit the same points in the same ascending order.
#include <bit>
#include <cstdint>

#include "simd.h"

namespace foton::kern {

// Calls visit(k) for every k in [begin, end) with |(x[k], y[k], z[k]) - q|^2 <= r2, in
// ascending k. The arrays are read up to end rounded up to a multiple of the SIMD width past
// begin: the caller pads them by kWidth.
template <class Visit>
inline void radius_scan(const float* x, const float* y, const float* z, uint32_t begin,
                        uint32_t end, const float q[3], float r2, Visit&& visit) {
    using simd::FloatV;
    const FloatV qx(q[0]), qy(q[1]), qz(q[2]), rr(r2);
    for (uint32_t k = begin; k < end; k += uint32_t(simd::kWidth)) {
        const FloatV ex = FloatV::load_unaligned(x + k) - qx;
        const FloatV ey = FloatV::load_unaligned(y + k) - qy;
        const FloatV ez = FloatV::load_unaligned(z + k) - qz;
        uint32_t bits = simd::movemask((ex * ex + ey * ey) + ez * ez <= rr);
        const uint32_t left = end - k;
        if (left < simd::kWidth) bits &= (1u << left) - 1u;
        for (; bits != 0; bits &= bits - 1) visit(k + uint32_t(std::countr_zero(bits)));
    }
}

template <class Visit>
inline void radius_scan_scalar(const float* x, const float* y, const float* z, uint32_t begin,
                               uint32_t end, const float q[3], float r2, Visit&& visit) {
    for (uint32_t k = begin; k < end; ++k) {
        const float ex = x[k] - q[0], ey = y[k] - q[1], ez = z[k] - q[2];
        if ((ex * ex + ey * ey) + ez * ez <= r2) visit(k);
    }
}

}  // namespace foton::kern
