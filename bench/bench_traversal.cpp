// Google Benchmark: ray traversal of one mesh, our uniform grid (kernels/) against raw Embree
// rtcIntersect1 / rtcOccluded1 on identical rays. Ray sets, generated deterministically:
//   primary: 1024 x 1024 pinhole camera framing the mesh (coherent);
//   diffuse: cosine directions from random surface points (incoherent);
//   shadow:  from random surface points to a point light (occlusion).
// Counters: rays/s (single thread). The ratio is grid / embree on the same ray set.
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "engine/scene/obj_loader.h"
#include "kernels/uniform_grid.h"

using namespace foton;
using foton::kern::Ray1;

namespace {

struct MeshData {
    TriangleMesh mesh;
    kern::UniformGrid grid;
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::map<std::string, std::vector<Ray1>> rays;
};

std::vector<Ray1> primary_rays(const Bounds3& b) {
    const Vec3 c = b.center(), ext = b.diagonal();
    const float r = 0.5f * length(ext);
    const Vec3 eye = c + normalize(Vec3{0.3f, 0.25f, 1.f}) * (2.8f * r);
    const Vec3 w = normalize(c - eye), u = normalize(cross(w, {0, 1, 0})), v = cross(u, w);
    const int n = 1024;
    const float half = std::tan(0.5f * 45.f * kPi / 180.f);
    std::vector<Ray1> rays;
    rays.reserve(std::size_t(n) * n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const float px = (2.f * (float(x) + 0.5f) / float(n) - 1.f) * half;
            const float py = (1.f - 2.f * (float(y) + 0.5f) / float(n)) * half;
            const Vec3 d = normalize(w + u * px + v * py);
            rays.push_back({eye.x, eye.y, eye.z, d.x, d.y, d.z, 0.f, kern::kInf});
        }
    return rays;
}

// Random points on the surface (area-weighted by picking triangles uniformly is close enough
// for a benchmark ray set) with their geometric normals.
void surface_points(const TriangleMesh& m, std::mt19937& rng, std::size_t n, std::vector<Vec3>& p,
                    std::vector<Vec3>& nrm) {
    std::uniform_real_distribution<float> U(0.f, 1.f);
    for (std::size_t i = 0; i < n; ++i) {
        Vec3 a, b, c;
        m.corners(uint32_t(rng() % m.num_triangles()), a, b, c);
        float s = U(rng), t = U(rng);
        if (s + t > 1.f) s = 1.f - s, t = 1.f - t;
        p.push_back(a + (b - a) * s + (c - a) * t);
        nrm.push_back(normalize(cross(b - a, c - a)));
    }
}

MeshData& data(const std::string& name) {
    static std::map<std::string, MeshData> all;
    auto it = all.find(name);
    if (it != all.end()) return it->second;
    MeshData& d = all[name];
    d.mesh = load_obj(std::string(FOTON_SOURCE_DIR) + "/../shared/meshes/" + name + ".obj").mesh;
    d.grid.build(d.mesh.positions.data(), d.mesh.indices.data(), d.mesh.num_triangles());
    d.device = rtcNewDevice(nullptr);
    d.scene = rtcNewScene(d.device);
    RTCGeometry g = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, d.mesh.num_vertices()));
    std::copy(d.mesh.positions.begin(), d.mesh.positions.end(), v);
    auto* ix = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, d.mesh.num_triangles()));
    std::copy(d.mesh.indices.begin(), d.mesh.indices.end(), ix);
    rtcCommitGeometry(g);
    rtcAttachGeometry(d.scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(d.scene);

    const Bounds3 b = d.mesh.bounds();
    d.rays["primary"] = primary_rays(b);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> U(0.f, 1.f);
    std::vector<Vec3> p, n;
    surface_points(d.mesh, rng, 1u << 18, p, n);
    const float eps = 1e-4f * length(b.diagonal());
    const Vec3 light = b.center() + Vec3{0.f, 2.f, 1.f} * length(b.diagonal());
    auto& diffuse = d.rays["diffuse"];
    auto& shadow = d.rays["shadow"];
    for (std::size_t i = 0; i < p.size(); ++i) {
        Vec3 s, t;
        orthonormal_basis(n[i], s, t);
        const float r = std::sqrt(U(rng)), phi = 2.f * kPi * U(rng);
        const float side = (i & 1) ? 1.f : -1.f;  // both sides of the (open) scanned surface
        const Vec3 w = s * (r * std::cos(phi)) + t * (r * std::sin(phi)) +
                       n[i] * (side * std::sqrt(std::max(0.f, 1.f - r * r)));
        const Vec3 o = p[i] + n[i] * (side * eps);
        diffuse.push_back({o.x, o.y, o.z, w.x, w.y, w.z, 0.f, kern::kInf});
        const Vec3 to = light - o;
        const float dist = length(to);
        const Vec3 l = to / dist;
        shadow.push_back({o.x, o.y, o.z, l.x, l.y, l.z, 0.f, dist});
    }
    return d;
}

RTCRayHit to_embree(const Ray1& r) {
    RTCRayHit rh;
    rh.ray = {r.ox, r.oy, r.oz, r.tmin, r.dx, r.dy, r.dz, 0.f, r.tmax, 0xffffffffu, 0, 0};
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return rh;
}

void report(benchmark::State& state, std::size_t rays, std::size_t hits) {
    state.counters["rays/s"] =
        benchmark::Counter(double(rays), benchmark::Counter::kIsIterationInvariantRate);
    state.counters["hit%"] = 100.0 * double(hits) / double(rays) / double(state.iterations());
}

void BM_Grid(benchmark::State& state, const std::string& mesh, const std::string& set) {
    MeshData& d = data(mesh);
    const auto& rays = d.rays[set];
    const bool occl = set == "shadow";
    std::size_t hits = 0;
    for (auto _ : state)
        for (const Ray1& r : rays) {
            if (occl) {
                hits += d.grid.occluded(r);
            } else {
                kern::TriHit h;
                hits += d.grid.intersect(r, h);
            }
        }
    report(state, rays.size(), hits);
}

void BM_Embree(benchmark::State& state, const std::string& mesh, const std::string& set) {
    MeshData& d = data(mesh);
    const auto& rays = d.rays[set];
    const bool occl = set == "shadow";
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    std::size_t hits = 0;
    for (auto _ : state)
        for (const Ray1& r : rays) {
            RTCRayHit rh = to_embree(r);
            if (occl) {
                rtcOccluded1(d.scene, &ctx, &rh.ray);
                hits += rh.ray.tfar == -kern::kInf;
            } else {
                rtcIntersect1(d.scene, &ctx, &rh);
                hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
            }
        }
    report(state, rays.size(), hits);
}

const bool registered = [] {
    for (const char* mesh : {"bunny", "teapot"})
        for (const char* set : {"primary", "diffuse", "shadow"}) {
            const std::string tag = std::string(mesh) + "/" + set;
            benchmark::RegisterBenchmark(("traversal/grid/" + tag).c_str(), BM_Grid, mesh, set)
                ->Unit(benchmark::kMillisecond);
            benchmark::RegisterBenchmark(("traversal/embree_rtcIntersect1/" + tag).c_str(),
                                         BM_Embree, mesh, set)
                ->Unit(benchmark::kMillisecond);
        }
    return true;
}();

}  // namespace

BENCHMARK_MAIN();
