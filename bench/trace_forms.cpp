#include "trace_forms.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <string>

namespace foton::bench {

using kern::Ray1;

RayColumns::RayColumns(const std::vector<Ray1>& r) {
    const std::size_t n = r.size();
    for (auto* c : {&ox, &oy, &oz, &dx, &dy, &dz, &tmin, &tmax, &t, &u, &v}) c->resize(n);
    id.resize(n);
    occluded.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        ox[i] = r[i].ox, oy[i] = r[i].oy, oz[i] = r[i].oz;
        dx[i] = r[i].dx, dy[i] = r[i].dy, dz[i] = r[i].dz;
        tmin[i] = r[i].tmin, tmax[i] = r[i].tmax;
    }
}

kern::RayStream RayColumns::rays(std::size_t b, std::size_t e) const {
    return {&ox[b], &oy[b], &oz[b], &dx[b], &dy[b], &dz[b], &tmin[b], &tmax[b], e - b};
}

kern::HitStream RayColumns::hits(std::size_t b) {
    return {&t[b], &u[b], &v[b], &id[b]};
}

// Rays per packet of our packet form.
constexpr std::size_t W = kern::kBlockWidth;

EmbreeColumns::EmbreeColumns(const std::vector<Ray1>& r) {
    const std::size_t n = r.size();
    for (auto* c : {&ox, &oy, &oz, &dx, &dy, &dz, &tnear, &tfar, &time, &ngx, &ngy, &ngz, &u, &v})
        c->resize(n);
    for (auto* c : {&mask, &id, &flags, &prim, &geom, &inst}) c->resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        ox[i] = r[i].ox, oy[i] = r[i].oy, oz[i] = r[i].oz;
        dx[i] = r[i].dx, dy[i] = r[i].dy, dz[i] = r[i].dz;
        tnear[i] = r[i].tmin, tfar[i] = r[i].tmax, time[i] = 0.f, mask[i] = 0xffffffffu;
    }
}

RTCRayNp EmbreeColumns::ray(std::size_t b) {
    return {&ox[b], &oy[b],   &oz[b],   &tnear[b], &dx[b], &dy[b],
            &dz[b], &time[b], &tfar[b], &mask[b],  &id[b], &flags[b]};
}

RTCRayHitNp EmbreeColumns::rayhit(std::size_t b) {
    RTCRayHitNp p;
    p.ray = ray(b);
    p.hit = {&ngx[b], &ngy[b], &ngz[b], &u[b], &v[b], &prim[b], &geom[b], {&inst[b]}};
    return p;
}

const char* quality_name(EmbreeQuality q) {
    return q == EmbreeQuality::High ? "high" : "medium";
}

namespace {

// Net bytes Embree holds, summed by its memory monitor (the device's allocations only).
std::atomic<long long> g_embree_bytes{0};

bool count_bytes(void*, ssize_t bytes, bool) {
    g_embree_bytes.fetch_add(bytes, std::memory_order_relaxed);
    return true;
}

}  // namespace

EmbreeDevice::EmbreeDevice(int threads) {
    const std::string cfg = threads > 0 ? "threads=" + std::to_string(threads) : "";
    device = rtcNewDevice(cfg.empty() ? nullptr : cfg.c_str());
    rtcSetDeviceMemoryMonitorFunction(device, count_bytes, nullptr);
}

EmbreeDevice::~EmbreeDevice() {
    rtcReleaseDevice(device);
}

EmbreeScene::EmbreeScene(RTCDevice device, const TriangleMesh& mesh, EmbreeQuality q) {
    scene = rtcNewScene(device);
    rtcSetSceneBuildQuality(
        scene, q == EmbreeQuality::High ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM);
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(
        g, q == EmbreeQuality::High ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, mesh.num_vertices()));
    std::copy(mesh.positions.begin(), mesh.positions.end(), v);
    auto* ix = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, mesh.num_triangles()));
    std::copy(mesh.indices.begin(), mesh.indices.end(), ix);
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    const long long before = g_embree_bytes.load();
    rtcCommitScene(scene);
    bytes = std::size_t(std::max(0ll, g_embree_bytes.load() - before));
}

EmbreeScene& EmbreeScene::operator=(EmbreeScene&& o) noexcept {
    std::swap(scene, o.scene);
    std::swap(bytes, o.bytes);
    return *this;
}

EmbreeScene::~EmbreeScene() {
    if (scene) rtcReleaseScene(scene);
}

std::vector<TraceForm> our_forms(const kern::TriangleBvh& bvh, const std::vector<Ray1>& rays,
                                 bool occlusion, bool coherent) {
    std::vector<TraceForm> f;
    f.push_back({"bvh", true, [&bvh, &rays, occlusion](std::size_t b, std::size_t e) {
                     std::size_t h = 0;
                     for (std::size_t i = b; i < e; ++i) {
                         if (occlusion) {
                             h += bvh.occluded(rays[i]);
                         } else {
                             kern::TriHit hit;
                             h += bvh.intersect(rays[i], hit);
                         }
                     }
                     return h;
                 }});
    auto cols = std::make_shared<RayColumns>(rays);
    for (const auto mode : {kern::StreamMode::Interleaved, kern::StreamMode::SortedPackets})
        f.push_back({mode == kern::StreamMode::Interleaved ? "bvh_stream" : "bvh_sorted_packets",
                     true, [&bvh, cols, occlusion, mode](std::size_t b, std::size_t e) {
                         std::size_t h = 0;
                         if (occlusion) {
                             bvh.occluded_stream(cols->rays(b, e), &cols->occluded[b], nullptr,
                                                 mode);
                             for (std::size_t i = b; i < e; ++i) h += cols->occluded[i];
                         } else {
                             bvh.intersect_stream(cols->rays(b, e), cols->hits(b), nullptr, mode);
                             for (std::size_t i = b; i < e; ++i)
                                 h += cols->id[i] != kern::kInvalidId;
                         }
                         return h;
                     }});
    if (!coherent) return f;
    // Packets of W consecutive rays (a 4x4 pixel square of the Morton-ordered camera rays).
    struct Packets {
        std::vector<kern::RayPacket> p;
        std::vector<std::array<float, W>> tmax;
    };
    auto pk = std::make_shared<Packets>();
    pk->p.resize((rays.size() + W - 1) / W);
    pk->tmax.resize(pk->p.size());
    for (std::size_t i = 0; i < rays.size(); ++i) {
        kern::RayPacket& k = pk->p[i / W];
        const std::size_t l = i % W;
        k.ox[l] = rays[i].ox, k.oy[l] = rays[i].oy, k.oz[l] = rays[i].oz;
        k.dx[l] = rays[i].dx, k.dy[l] = rays[i].dy, k.dz[l] = rays[i].dz, k.tmin[l] = rays[i].tmin;
        pk->tmax[i / W][l] = rays[i].tmax;
    }
    f.push_back({"bvh_packet", true, [&bvh, pk, occlusion](std::size_t b, std::size_t e) {
                     std::size_t h = 0;
                     for (std::size_t first = b; first < e; first += W) {
                         const std::size_t n = std::min(W, e - first);
                         const uint32_t active = n >= 32 ? ~0u : (1u << n) - 1u;
                         const std::size_t p = first / W;
                         if (occlusion) {
                             h += std::size_t(__builtin_popcount(
                                 bvh.occluded_packet(pk->p[p], pk->tmax[p].data(), active)));
                             continue;
                         }
                         kern::PacketHits ph;
                         for (std::size_t l = 0; l < W; ++l)
                             ph.t[l] = pk->tmax[p][l], ph.u[l] = ph.v[l] = 0.f,
                             ph.id[l] = kern::kInvalidId;
                         bvh.intersect_packet(pk->p[p], active, ph);
                         for (std::size_t l = 0; l < n; ++l) h += ph.id[l] != kern::kInvalidId;
                     }
                     return h;
                 }});
    return f;
}

namespace {

RTCRay embree_ray(const Ray1& r) {
    RTCRay e;
    e.org_x = r.ox, e.org_y = r.oy, e.org_z = r.oz, e.tnear = r.tmin;
    e.dir_x = r.dx, e.dir_y = r.dy, e.dir_z = r.dz, e.time = 0.f;
    e.tfar = r.tmax, e.mask = 0xffffffffu, e.id = 0, e.flags = 0;
    return e;
}

template <int K>
struct Packet;
template <>
struct Packet<8> {
    using RayHit = RTCRayHit8;
    static void hit(const int* v, RTCScene s, RTCIntersectContext* c, RTCRayHit8* r) {
        rtcIntersect8(v, s, c, r);
    }
    static void occ(const int* v, RTCScene s, RTCIntersectContext* c, RTCRay8* r) {
        rtcOccluded8(v, s, c, r);
    }
};
template <>
struct Packet<16> {
    using RayHit = RTCRayHit16;
    static void hit(const int* v, RTCScene s, RTCIntersectContext* c, RTCRayHit16* r) {
        rtcIntersect16(v, s, c, r);
    }
    static void occ(const int* v, RTCScene s, RTCIntersectContext* c, RTCRay16* r) {
        rtcOccluded16(v, s, c, r);
    }
};

template <int K>
TraceForm packet_form(const std::string& prefix, RTCScene scene, const std::vector<Ray1>& rays,
                      bool occlusion) {
    using P = Packet<K>;
    auto packets = std::make_shared<std::vector<typename P::RayHit>>((rays.size() + K - 1) / K);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        auto& r = (*packets)[i / K].ray;
        const int l = int(i % K);
        r.org_x[l] = rays[i].ox, r.org_y[l] = rays[i].oy, r.org_z[l] = rays[i].oz;
        r.dir_x[l] = rays[i].dx, r.dir_y[l] = rays[i].dy, r.dir_z[l] = rays[i].dz;
        r.tnear[l] = rays[i].tmin, r.time[l] = 0.f, r.mask[l] = 0xffffffffu;
        r.id[l] = 0, r.flags[l] = 0;
    }
    const std::string name =
        prefix + (occlusion ? "rtcOccluded" : "rtcIntersect") + std::to_string(K);
    return {name, false, [scene, &rays, packets, occlusion](std::size_t b, std::size_t e) {
                RTCIntersectContext ctx;
                rtcInitIntersectContext(&ctx);
                alignas(64) int valid[K];
                std::size_t h = 0;
                for (std::size_t i = b; i < e; i += K) {
                    auto& p = (*packets)[i / K];
                    for (int l = 0; l < K; ++l) {
                        const bool in = i + std::size_t(l) < e;
                        valid[l] = in ? -1 : 0;
                        p.ray.tfar[l] = in ? rays[i + std::size_t(l)].tmax : 0.f;
                        p.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
                        p.hit.instID[0][l] = RTC_INVALID_GEOMETRY_ID;
                    }
                    if (occlusion) {
                        P::occ(valid, scene, &ctx, &p.ray);
                        for (int l = 0; l < K; ++l) h += valid[l] && p.ray.tfar[l] == -kern::kInf;
                    } else {
                        P::hit(valid, scene, &ctx, &p);
                        for (int l = 0; l < K; ++l)
                            h += valid[l] && p.hit.geomID[l] != RTC_INVALID_GEOMETRY_ID;
                    }
                }
                return h;
            }};
}

}  // namespace

std::vector<TraceForm> embree_forms(RTCScene scene, EmbreeQuality q, const std::vector<Ray1>& rays,
                                    bool occlusion, bool coherent) {
    const std::string prefix = std::string("embree_") + quality_name(q) + "/";
    std::vector<TraceForm> f;
    f.push_back({prefix + (occlusion ? "rtcOccluded1" : "rtcIntersect1"), false,
                 [scene, &rays, occlusion](std::size_t b, std::size_t e) {
                     RTCIntersectContext ctx;
                     rtcInitIntersectContext(&ctx);
                     std::size_t h = 0;
                     for (std::size_t i = b; i < e; ++i) {
                         RTCRayHit rh;
                         rh.ray = embree_ray(rays[i]);
                         rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                         rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                         if (occlusion) {
                             rtcOccluded1(scene, &ctx, &rh.ray);
                             h += rh.ray.tfar == -kern::kInf;
                         } else {
                             rtcIntersect1(scene, &ctx, &rh);
                             h += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
                         }
                     }
                     return h;
                 }});
    f.push_back(packet_form<8>(prefix, scene, rays, occlusion));
    f.push_back(packet_form<16>(prefix, scene, rays, occlusion));
    const RTCIntersectContextFlags flag =
        coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    auto aos = std::make_shared<std::vector<RTCRayHit>>(rays.size());
    f.push_back({prefix + (occlusion ? "rtcOccluded1M" : "rtcIntersect1M"), false,
                 [scene, &rays, aos, occlusion, flag](std::size_t b, std::size_t e) {
                     RTCIntersectContext ctx;
                     rtcInitIntersectContext(&ctx);
                     ctx.flags = flag;
                     auto& s = *aos;
                     for (std::size_t i = b; i < e; ++i) {
                         s[i].ray = embree_ray(rays[i]);
                         s[i].hit.geomID = RTC_INVALID_GEOMETRY_ID;
                         s[i].hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                     }
                     std::size_t h = 0;
                     if (occlusion) {
                         rtcOccluded1M(scene, &ctx, &s[b].ray, unsigned(e - b), sizeof(RTCRayHit));
                         for (std::size_t i = b; i < e; ++i) h += s[i].ray.tfar == -kern::kInf;
                     } else {
                         rtcIntersect1M(scene, &ctx, &s[b], unsigned(e - b), sizeof(RTCRayHit));
                         for (std::size_t i = b; i < e; ++i)
                             h += s[i].hit.geomID != RTC_INVALID_GEOMETRY_ID;
                     }
                     return h;
                 }});
    auto soa = std::make_shared<EmbreeColumns>(rays);
    f.push_back({prefix + (occlusion ? "rtcOccludedNp" : "rtcIntersectNp"), false,
                 [scene, &rays, soa, occlusion, flag](std::size_t b, std::size_t e) {
                     RTCIntersectContext ctx;
                     rtcInitIntersectContext(&ctx);
                     ctx.flags = flag;
                     EmbreeColumns& s = *soa;
                     for (std::size_t i = b; i < e; ++i) {
                         s.tfar[i] = rays[i].tmax;
                         s.geom[i] = RTC_INVALID_GEOMETRY_ID;
                         s.inst[i] = RTC_INVALID_GEOMETRY_ID;
                     }
                     std::size_t h = 0;
                     if (occlusion) {
                         const RTCRayNp r = s.ray(b);
                         rtcOccludedNp(scene, &ctx, &r, unsigned(e - b));
                         for (std::size_t i = b; i < e; ++i) h += s.tfar[i] == -kern::kInf;
                     } else {
                         RTCRayHitNp r = s.rayhit(b);
                         rtcIntersectNp(scene, &ctx, &r, unsigned(e - b));
                         for (std::size_t i = b; i < e; ++i)
                             h += s.geom[i] != RTC_INVALID_GEOMETRY_ID;
                     }
                     return h;
                 }});
    return f;
}

}  // namespace foton::bench
