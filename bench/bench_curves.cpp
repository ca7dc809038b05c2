// Google Benchmark: rays against curves, foton's curve kernel in its BVH (kernels/curve_bvh.h)
// against Embree's flat Bézier curves (RTC_GEOMETRY_TYPE_FLAT_BEZIER_CURVE, the same ray-facing
// ribbons) on identical rays, one thread: a block of 20,000 wavy hairs of 5 cubic segments each
// (100,000 segments, width 0.004 tapering to 0.002 in a 2 x 2 x 0.6 box), seen by 65,536
// primary rays from a pinhole camera and by 65,536 incoherent rays from random points inside
// the block in random directions. Rays per second; both sides count their hits so the work is
// checked alike. foton's rays go one by one (`foton_curve_bvh`, closest()) and as one stream
// (`foton_curve_bvh_stream`, closest_stream(): eight walks interleaved), Embree's by
// rtcIntersect1 and as one rtcIntersect1M stream (`embree_flat_bezier_1M`). Names:
// curves/<set>/<method>.
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <cmath>
#include <random>
#include <vector>

#include "kernels/curve_bvh.h"

using namespace foton::kern;

namespace {

constexpr int kRays = 65536;

struct HairBlock {
    std::vector<CurveSegment> segments;
    std::vector<Ray1> primary, incoherent;
    HairBlock() {
        std::mt19937 r(36);
        std::uniform_real_distribution<float> u(0.f, 1.f);
        for (int s = 0; s < 20000; ++s) {
            const float x = 2.f * u(r) - 1.f, z = 0.6f * u(r) - 0.3f, phase = 6.283f * u(r);
            float p[16][3];
            for (int k = 0; k < 16; ++k) {
                const float y = 1.f - 2.f * float(k) / 15.f;
                p[k][0] = x + 0.03f * std::sin(phase + 0.9f * float(k));
                p[k][1] = y;
                p[k][2] = z + 0.03f * std::cos(phase + 0.7f * float(k));
            }
            for (int seg = 0; seg < 5; ++seg) {
                CurveSegment c;
                for (int k = 0; k < 4; ++k)
                    for (int a = 0; a < 3; ++a) c.cp[k][a] = p[3 * seg + k][a];
                c.w0 = 0.004f - 0.0004f * float(seg);
                c.w1 = c.w0 - 0.0004f;
                segments.push_back(c);
            }
        }
        for (int i = 0; i < kRays; ++i) {
            // 256 x 256 pixels of a camera at z = -3 looking at the block.
            const float sx = (float(i % 256) + 0.5f) / 256.f * 2.f - 1.f;
            const float sy = (float(i / 256) + 0.5f) / 256.f * 2.f - 1.f;
            const float dx = 0.4f * sx, dy = 0.4f * sy, dz = 1.f;
            const float l = std::sqrt(dx * dx + dy * dy + dz * dz);
            primary.push_back({0.f, 0.f, -3.f, dx / l, dy / l, dz / l, 0.f, kInf});
            const float ct = 2.f * u(r) - 1.f, st = std::sqrt(1.f - ct * ct), ph = 6.283f * u(r);
            incoherent.push_back({2.f * u(r) - 1.f, 2.f * u(r) - 1.f, 0.6f * u(r) - 0.3f,
                                  st * std::cos(ph), st * std::sin(ph), ct, 0.f, kInf});
        }
    }
};

const HairBlock& block() {
    static const HairBlock b;
    return b;
}

const std::vector<Ray1>& rays_of(int set) {
    return set == 0 ? block().primary : block().incoherent;
}

const CurveBvh& curve_bvh() {
    static const CurveBvh bvh(block().segments, std::vector<uint8_t>(block().segments.size(), 0));
    return bvh;
}

void BM_foton(benchmark::State& state) {
    const CurveBvh& bvh = curve_bvh();
    const std::vector<Ray1>& rays = rays_of(int(state.range(0)));
    std::size_t hits = 0;
    uint64_t tests = 0;
    for (auto _ : state) {
        hits = 0;
        for (const Ray1& ray : rays) {
            CurveHit h;
            uint32_t id;
            hits += bvh.closest(ray, h, id, tests) ? 1 : 0;
        }
        benchmark::DoNotOptimize(hits);
    }
    state.counters["hit_fraction"] = double(hits) / double(rays.size());
    state.counters["tests_per_ray"] =
        double(tests) / double(rays.size()) / double(state.iterations());
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(rays.size()));
}

// The same rays as one stream (CurveBvh::closest_stream: walks interleaved).
void BM_foton_stream(benchmark::State& state) {
    const CurveBvh& bvh = curve_bvh();
    const std::vector<Ray1>& rays = rays_of(int(state.range(0)));
    std::vector<CurveHit> hits(rays.size());
    std::vector<uint32_t> ids(rays.size());
    std::vector<uint8_t> found(rays.size());
    std::size_t n_hits = 0;
    uint64_t tests = 0;
    for (auto _ : state) {
        for (CurveHit& h : hits) h = CurveHit{};
        bvh.closest_stream(rays.data(), rays.size(), hits.data(), ids.data(), found.data(), tests);
        n_hits = 0;
        for (const uint8_t f : found) n_hits += f;
        benchmark::DoNotOptimize(n_hits);
    }
    state.counters["hit_fraction"] = double(n_hits) / double(rays.size());
    state.counters["tests_per_ray"] =
        double(tests) / double(rays.size()) / double(state.iterations());
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(rays.size()));
}

struct EmbreeCurves {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    EmbreeCurves() {
        const HairBlock& b = block();
        device = rtcNewDevice("threads=1");
        scene = rtcNewScene(device);
        RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_FLAT_BEZIER_CURVE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0,
                                                              RTC_FORMAT_FLOAT4, 4 * sizeof(float),
                                                              4 * b.segments.size()));
        auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
            g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, sizeof(unsigned), b.segments.size()));
        for (std::size_t s = 0; s < b.segments.size(); ++s) {
            const CurveSegment& c = b.segments[s];
            for (int k = 0; k < 4; ++k) {
                float* q = v + 4 * (4 * s + std::size_t(k));
                q[0] = c.cp[k][0], q[1] = c.cp[k][1], q[2] = c.cp[k][2];
                // A linear width as a cubic's radii: the control values of a line.
                q[3] = 0.5f * (c.w0 + (c.w1 - c.w0) * float(k) / 3.f);
            }
            idx[s] = unsigned(4 * s);
        }
        rtcCommitGeometry(g);
        rtcAttachGeometry(scene, g);
        rtcReleaseGeometry(g);
        rtcCommitScene(scene);
    }
    ~EmbreeCurves() {
        rtcReleaseScene(scene);
        rtcReleaseDevice(device);
    }
};

void BM_embree(benchmark::State& state) {
    static const EmbreeCurves e;
    const std::vector<Ray1>& rays = rays_of(int(state.range(0)));
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    std::size_t hits = 0;
    for (auto _ : state) {
        hits = 0;
        for (const Ray1& r : rays) {
            RTCRayHit rh{};
            rh.ray.org_x = r.ox, rh.ray.org_y = r.oy, rh.ray.org_z = r.oz;
            rh.ray.dir_x = r.dx, rh.ray.dir_y = r.dy, rh.ray.dir_z = r.dz;
            rh.ray.tnear = r.tmin;
            rh.ray.tfar = r.tmax;
            rh.ray.mask = ~0u;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(e.scene, &ctx, &rh);
            hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID ? 1 : 0;
        }
        benchmark::DoNotOptimize(hits);
    }
    state.counters["hit_fraction"] = double(hits) / double(rays.size());
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(rays.size()));
}

// Embree's stream form for the same rays: rtcIntersect1M over the whole set (incoherent flag
// for the random rays, coherent for the camera's), what foton's stream is measured against.
void BM_embree_stream(benchmark::State& state) {
    static const EmbreeCurves e;
    const std::vector<Ray1>& rays = rays_of(int(state.range(0)));
    std::vector<RTCRayHit> rh(rays.size());
    std::size_t hits = 0;
    for (auto _ : state) {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        ctx.flags = state.range(0) == 0 ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT
                                        : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const Ray1& r = rays[i];
            rh[i] = RTCRayHit{};
            rh[i].ray.org_x = r.ox, rh[i].ray.org_y = r.oy, rh[i].ray.org_z = r.oz;
            rh[i].ray.dir_x = r.dx, rh[i].ray.dir_y = r.dy, rh[i].ray.dir_z = r.dz;
            rh[i].ray.tnear = r.tmin;
            rh[i].ray.tfar = r.tmax;
            rh[i].ray.mask = ~0u;
            rh[i].hit.geomID = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect1M(e.scene, &ctx, rh.data(), unsigned(rh.size()), sizeof(RTCRayHit));
        hits = 0;
        for (const RTCRayHit& h : rh) hits += h.hit.geomID != RTC_INVALID_GEOMETRY_ID ? 1 : 0;
        benchmark::DoNotOptimize(hits);
    }
    state.counters["hit_fraction"] = double(hits) / double(rays.size());
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(rays.size()));
}

}  // namespace

BENCHMARK(BM_foton)->Name("curves/primary/foton_curve_bvh")->Arg(0)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_foton_stream)
    ->Name("curves/primary/foton_curve_bvh_stream")
    ->Arg(0)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_embree)
    ->Name("curves/primary/embree_flat_bezier")
    ->Arg(0)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_embree_stream)
    ->Name("curves/primary/embree_flat_bezier_1M")
    ->Arg(0)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_foton)
    ->Name("curves/incoherent/foton_curve_bvh")
    ->Arg(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_foton_stream)
    ->Name("curves/incoherent/foton_curve_bvh_stream")
    ->Arg(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_embree)
    ->Name("curves/incoherent/embree_flat_bezier")
    ->Arg(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_embree_stream)
    ->Name("curves/incoherent/embree_flat_bezier_1M")
    ->Arg(1)
    ->Unit(benchmark::kMillisecond);
