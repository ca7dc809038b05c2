#pragma once
// SoA views of a batch of rays and of their closest hits, for the stream kernels (whole batches
// in one call). Plain pointers, so the engine's RayBatch / HitBatch columns and a benchmark's
// arrays pass without a copy.
#include <cstddef>
#include <cstdint>

#include "ray1.h"

namespace foton::kern {

struct RayStream {
    const float *ox = nullptr, *oy = nullptr, *oz = nullptr;
    const float *dx = nullptr, *dy = nullptr, *dz = nullptr;
    const float *tmin = nullptr, *tmax = nullptr;
    std::size_t count = 0;

    Ray1 ray(std::size_t i) const {
        return {ox[i], oy[i], oz[i], dx[i], dy[i], dz[i], tmin[i], tmax[i]};
    }
};

// Closest hits: t is the ray's tmax and id kInvalidId where nothing was hit (u, v then 0).
struct HitStream {
    float *t = nullptr, *u = nullptr, *v = nullptr;
    uint32_t* id = nullptr;

    void set(std::size_t i, const TriHit& h) const {
        t[i] = h.t;
        u[i] = h.u;
        v[i] = h.v;
        id[i] = h.id;
    }
};

}  // namespace foton::kern
