#pragma once
// The SoA containers that move rays and hits between the stages of a wavefront.
#include <cstdint>

#include "aligned.h"
#include "math.h"

namespace foton {

inline constexpr uint32_t kNoHit = 0xffffffffu;

struct RayBatch {
    AlignedVector<float> ox, oy, oz, dx, dy, dz, tmin, tmax;
    AlignedVector<uint32_t> id;  // the slot (pixel sample, path, photon) the ray belongs to
    // Set by the stage that makes the batch when neighbouring rays are nearly parallel and
    // start close together (camera rays in pixel order), so a backend may trace them as
    // packets; bounce and photon batches are not. clear() resets it.
    bool coherent = false;

    std::size_t size() const { return id.size(); }
    bool empty() const { return id.empty(); }
    void clear();
    void reserve(std::size_t n);
    // n rays; those past the old size are set by the caller, column by column.
    void resize(std::size_t n);
    void push(const Vec3& o, const Vec3& d, float t0, float t1, uint32_t slot);
    Vec3 origin(std::size_t i) const { return {ox[i], oy[i], oz[i]}; }
    Vec3 direction(std::size_t i) const { return {dx[i], dy[i], dz[i]}; }
};

// Closest-hit results; normals and shading frames are derived on demand by the stage that
// needs them. geom == kNoHit marks a miss.
struct HitBatch {
    AlignedVector<float> t, u, v;
    AlignedVector<uint32_t> prim, geom;

    std::size_t size() const { return t.size(); }
    void resize(std::size_t n);
};

inline void RayBatch::clear() {
    ox.clear();
    oy.clear();
    oz.clear();
    dx.clear();
    dy.clear();
    dz.clear();
    tmin.clear();
    tmax.clear();
    id.clear();
    coherent = false;
}

inline void RayBatch::reserve(std::size_t n) {
    ox.reserve(n);
    oy.reserve(n);
    oz.reserve(n);
    dx.reserve(n);
    dy.reserve(n);
    dz.reserve(n);
    tmin.reserve(n);
    tmax.reserve(n);
    id.reserve(n);
}

inline void RayBatch::resize(std::size_t n) {
    ox.resize(n);
    oy.resize(n);
    oz.resize(n);
    dx.resize(n);
    dy.resize(n);
    dz.resize(n);
    tmin.resize(n);
    tmax.resize(n);
    id.resize(n);
}

inline void RayBatch::push(const Vec3& o, const Vec3& d, float t0, float t1, uint32_t slot) {
    ox.push_back(o.x);
    oy.push_back(o.y);
    oz.push_back(o.z);
    dx.push_back(d.x);
    dy.push_back(d.y);
    dz.push_back(d.z);
    tmin.push_back(t0);
    tmax.push_back(t1);
    id.push_back(slot);
}

inline void HitBatch::resize(std::size_t n) {
    t.resize(n);
    u.resize(n);
    v.resize(n);
    prim.resize(n);
    geom.resize(n);
}

}  // namespace foton
