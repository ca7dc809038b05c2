#pragma once
// The ways a batch of rays can be traced, ours and Embree's, behind one call shape, so that a
// comparison runs every form on the same rays, chunk by chunk (bench/compare_embree.cpp).
// A form traces rays [begin, end) of its set (resetting each ray's tmax and hit first, as any
// renderer must) and returns how many of them hit something.
#include <embree3/rtcore.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "engine/scene/mesh.h"
#include "kernels/ray1.h"
#include "kernels/ray_stream.h"
#include "kernels/triangle_bvh.h"

namespace foton::bench {

// The rays of a set as SoA columns (the layout of the engine's RayBatch) with room for hits.
struct RayColumns {
    std::vector<float> ox, oy, oz, dx, dy, dz, tmin, tmax, t, u, v;
    std::vector<uint32_t> id;
    std::vector<uint8_t> occluded;
    explicit RayColumns(const std::vector<kern::Ray1>& rays);
    kern::RayStream rays(std::size_t begin, std::size_t end) const;
    kern::HitStream hits(std::size_t begin);
};

// The same rays as the SoA columns of Embree's rtcIntersectNp / rtcOccludedNp, with room for
// the hits; views of them pass without a copy.
struct EmbreeColumns {
    std::vector<float> ox, oy, oz, dx, dy, dz, tnear, tfar, time, ngx, ngy, ngz, u, v;
    std::vector<unsigned> mask, id, flags, prim, geom, inst;
    explicit EmbreeColumns(const std::vector<kern::Ray1>& rays);
    RTCRayNp ray(std::size_t begin);
    RTCRayHitNp rayhit(std::size_t begin);
};

// Embree's build quality: RTC_BUILD_QUALITY_MEDIUM (its default) or HIGH (spatial splits; what
// the engine's embree backend uses).
enum class EmbreeQuality { Medium, High };
const char* quality_name(EmbreeQuality q);

// A scene of one triangle mesh on an Embree device, with the bytes its build allocated.
struct EmbreeScene {
    RTCScene scene = nullptr;
    std::size_t bytes = 0;  // net allocation of rtcCommitScene: the BVH and its triangles
    EmbreeScene() = default;
    EmbreeScene(RTCDevice device, const TriangleMesh& mesh, EmbreeQuality q);
    EmbreeScene(EmbreeScene&& o) noexcept : scene(o.scene), bytes(o.bytes) { o.scene = nullptr; }
    EmbreeScene& operator=(EmbreeScene&& o) noexcept;
    ~EmbreeScene();
};

// An Embree device whose allocations are counted (for EmbreeScene::bytes); threads = 0: all.
struct EmbreeDevice {
    RTCDevice device = nullptr;
    explicit EmbreeDevice(int threads);
    ~EmbreeDevice();
    EmbreeDevice(const EmbreeDevice&) = delete;
    EmbreeDevice& operator=(const EmbreeDevice&) = delete;
};

struct TraceForm {
    std::string name;  // "bvh", "embree_medium/rtcIntersect1", ...
    bool ours = false;
    std::function<std::size_t(std::size_t begin, std::size_t end)> run;
};

// The forms for one ray set. `occlusion` selects any-hit forms; `coherent` marks camera rays
// (our packets, Embree's coherent stream flag). The structures must outlive the forms.
std::vector<TraceForm> our_forms(const kern::TriangleBvh& bvh, const std::vector<kern::Ray1>& rays,
                                 bool occlusion, bool coherent);
std::vector<TraceForm> embree_forms(RTCScene scene, EmbreeQuality q,
                                    const std::vector<kern::Ray1>& rays, bool occlusion,
                                    bool coherent);

}  // namespace foton::bench
