#include "embree_accel.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

#include "instance_layer.h"
#include "kernels/moller_trumbore.h"

namespace foton {

namespace {

// Embree calls this from C code, so it must not throw; the constructor checks the device's
// error state after the build instead.
void error_handler(void*, RTCError code, const char* str) {
    std::fprintf(stderr, "embree error %d: %s\n", int(code), str ? str : "");
}

void sphere_bounds(const RTCBoundsFunctionArguments* args) {
    const Sphere& s = *static_cast<const Sphere*>(args->geometryUserPtr);
    RTCBounds* b = args->bounds_o;
    b->lower_x = s.center.x - s.radius;
    b->lower_y = s.center.y - s.radius;
    b->lower_z = s.center.z - s.radius;
    b->upper_x = s.center.x + s.radius;
    b->upper_y = s.center.y + s.radius;
    b->upper_z = s.center.z + s.radius;
}

void sphere_intersect(const RTCIntersectFunctionNArguments* args) {
    const Sphere& s = *static_cast<const Sphere*>(args->geometryUserPtr);
    RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, args->N);
    RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, args->N);
    for (unsigned i = 0; i < args->N; ++i) {
        if (!args->valid[i]) continue;
        const Vec3 o{RTCRayN_org_x(ray, args->N, i), RTCRayN_org_y(ray, args->N, i),
                     RTCRayN_org_z(ray, args->N, i)};
        const Vec3 d{RTCRayN_dir_x(ray, args->N, i), RTCRayN_dir_y(ray, args->N, i),
                     RTCRayN_dir_z(ray, args->N, i)};
        float t;
        if (!intersect_sphere(s, o, d, RTCRayN_tnear(ray, args->N, i),
                              RTCRayN_tfar(ray, args->N, i), t))
            continue;
        const Vec3 n = o + d * t - s.center;
        RTCRayN_tfar(ray, args->N, i) = t;
        RTCHitN_Ng_x(hit, args->N, i) = n.x;
        RTCHitN_Ng_y(hit, args->N, i) = n.y;
        RTCHitN_Ng_z(hit, args->N, i) = n.z;
        RTCHitN_u(hit, args->N, i) = 0.f;
        RTCHitN_v(hit, args->N, i) = 0.f;
        RTCHitN_primID(hit, args->N, i) = args->primID;
        RTCHitN_geomID(hit, args->N, i) = args->geomID;
        RTCHitN_instID(hit, args->N, i, 0) = args->context->instID[0];
    }
}

void sphere_occluded(const RTCOccludedFunctionNArguments* args) {
    const Sphere& s = *static_cast<const Sphere*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i) {
        if (!args->valid[i]) continue;
        const Vec3 o{RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                     RTCRayN_org_z(args->ray, args->N, i)};
        const Vec3 d{RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                     RTCRayN_dir_z(args->ray, args->N, i)};
        float t;
        if (intersect_sphere(s, o, d, RTCRayN_tnear(args->ray, args->N, i),
                             RTCRayN_tfar(args->ray, args->N, i), t))
            RTCRayN_tfar(args->ray, args->N, i) = -kInfinity;
    }
}

}  // namespace

EmbreeAccel::EmbreeAccel(const Scene& scene, int threads) : scene_(scene) {
    const std::string config = threads > 0 ? "threads=" + std::to_string(threads) : "";
    device_ = rtcNewDevice(config.empty() ? nullptr : config.c_str());
    if (!device_) throw std::runtime_error("cannot create an Embree device");
    rtcSetDeviceErrorFunction(device_, error_handler, nullptr);
    rtc_scene_ = rtcNewScene(device_);
    rtcSetSceneBuildQuality(rtc_scene_, RTC_BUILD_QUALITY_HIGH);
    // A mesh as an Embree triangle geometry.
    auto triangles = [&](const TriangleMesh& m) {
        RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        // Embree-owned copies: its buffers need padding for vector loads past the end.
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0,
                                                              RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                              m.num_vertices()));
        std::memcpy(v, m.positions.data(), m.positions.size() * sizeof(float));
        auto* ix = static_cast<uint32_t*>(
            rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(uint32_t), m.num_triangles()));
        std::memcpy(ix, m.indices.data(), m.indices.size() * sizeof(uint32_t));
        memory_ += m.memory_bytes();
        return geom;
    };
    std::vector<int> child_of_mesh(scene.meshes.size(), -1);
    for (uint32_t g = 0; g < scene.objects.size(); ++g) {
        const Object& o = scene.objects[g];
        if (!traced_by_backend(o.kind)) continue;  // the wrappers'
        RTCGeometry geom;
        if (o.instance >= 0) {
            int& child = child_of_mesh[o.index];
            if (child < 0) {
                RTCScene cs = rtcNewScene(device_);
                rtcSetSceneBuildQuality(cs, RTC_BUILD_QUALITY_HIGH);
                RTCGeometry tg = triangles(scene.meshes[o.index]);
                rtcCommitGeometry(tg);
                rtcAttachGeometryByID(cs, tg, 0);
                rtcReleaseGeometry(tg);
                rtcCommitScene(cs);
                child = int(child_scenes_.size());
                child_scenes_.push_back(cs);
            }
            geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
            rtcSetGeometryInstancedScene(geom, child_scenes_[std::size_t(child)]);
            const Affine& xf = scene.instances[std::size_t(o.instance)].to_world;
            rtcSetGeometryTransform(geom, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, &xf.m[0][0]);
        } else if (o.kind == ObjectKind::Mesh) {
            geom = triangles(scene.meshes[o.index]);
        } else {
            geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
            rtcSetGeometryUserPrimitiveCount(geom, 1);
            rtcSetGeometryUserData(geom, const_cast<Sphere*>(&scene.spheres[o.index]));
            rtcSetGeometryBoundsFunction(geom, sphere_bounds, nullptr);
            rtcSetGeometryIntersectFunction(geom, sphere_intersect);
            rtcSetGeometryOccludedFunction(geom, sphere_occluded);
        }
        rtcCommitGeometry(geom);
        rtcAttachGeometryByID(rtc_scene_, geom, g);
        rtcReleaseGeometry(geom);
    }
    rtcCommitScene(rtc_scene_);
    if (rtcGetDeviceError(device_) != RTC_ERROR_NONE)
        throw std::runtime_error("Embree failed to build the scene");
}

EmbreeAccel::~EmbreeAccel() {
    if (rtc_scene_) rtcReleaseScene(rtc_scene_);
    for (RTCScene cs : child_scenes_) rtcReleaseScene(cs);
    if (device_) rtcReleaseDevice(device_);
}

bool EmbreeAccel::closest(const kern::Ray1& ray, Hit1& hit, TraceCounters&) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    rh.ray.org_x = ray.ox;
    rh.ray.org_y = ray.oy;
    rh.ray.org_z = ray.oz;
    rh.ray.dir_x = ray.dx;
    rh.ray.dir_y = ray.dy;
    rh.ray.dir_z = ray.dz;
    rh.ray.tnear = ray.tmin;
    rh.ray.tfar = std::min(ray.tmax, hit.t);
    rh.ray.time = 0.f;
    rh.ray.mask = 0xffffffffu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(rtc_scene_, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    hit = Hit1{rh.ray.tfar, rh.hit.u, rh.hit.v, rh.hit.primID, geometry_of(rh.hit)};
    reevaluate(ray, hit);
    return true;
}

void EmbreeAccel::reevaluate(const kern::Ray1& ray, Hit1& hit) const {
    const Object& o = scene_.objects[hit.geom];
    if (o.kind != ObjectKind::Mesh) return;
    const TriangleMesh& m = scene_.meshes[o.index];
    Vec3 p0, p1, p2;
    m.corners(hit.prim, p0, p1, p2);
    const Vec3 e1 = p1 - p0, e2 = p2 - p0;
    // An instance's triangle is tested in its own space, as the instance layer does.
    const kern::Ray1 r =
        o.instance >= 0 ? to_instance_space(scene_.instances[std::size_t(o.instance)], ray) : ray;
    float t, u, v;
    if (kern::intersect_triangle_scalar(r, p0.x, p0.y, p0.z, e1.x, e1.y, e1.z, e2.x, e2.y, e2.z,
                                        kInfinity, t, u, v)) {
        hit.t = t;
        hit.u = u;
        hit.v = v;
    }
}

bool EmbreeAccel::any(const kern::Ray1& ray, TraceCounters&) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay r;
    r.org_x = ray.ox;
    r.org_y = ray.oy;
    r.org_z = ray.oz;
    r.dir_x = ray.dx;
    r.dir_y = ray.dy;
    r.dir_z = ray.dz;
    r.tnear = ray.tmin;
    r.tfar = ray.tmax;
    r.time = 0.f;
    r.mask = 0xffffffffu;
    r.id = 0;
    r.flags = 0;
    rtcOccluded1(rtc_scene_, &ctx, &r);
    return r.tfar == -kInfinity;
}

namespace {

RTCIntersectContext batch_context(bool coherent) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags =
        coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    return ctx;
}

void fill_ray(const RayBatch& rays, std::size_t i, RTCRay& r) {
    r.org_x = rays.ox[i];
    r.org_y = rays.oy[i];
    r.org_z = rays.oz[i];
    r.dir_x = rays.dx[i];
    r.dir_y = rays.dy[i];
    r.dir_z = rays.dz[i];
    r.tnear = rays.tmin[i];
    r.tfar = rays.tmax[i];
    r.time = 0.f;
    r.mask = 0xffffffffu;
    r.id = uint32_t(i);
    r.flags = 0;
}

// Rays per stream call: large enough for Embree to sort them into packets, small enough to
// stay in cache.
constexpr std::size_t kStream = 1024;

}  // namespace

void EmbreeAccel::intersect(const RayBatch& rays, HitBatch& hits, TraceCounters&) const {
    hits.resize(rays.size());
    thread_local std::vector<RTCRayHit> stream;
    RTCIntersectContext ctx = batch_context(rays.coherent);
    for (std::size_t first = 0; first < rays.size(); first += kStream) {
        const std::size_t n = std::min(kStream, rays.size() - first);
        stream.resize(n);
        for (std::size_t k = 0; k < n; ++k) {
            fill_ray(rays, first + k, stream[k].ray);
            stream[k].hit.geomID = RTC_INVALID_GEOMETRY_ID;
            stream[k].hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect1M(rtc_scene_, &ctx, stream.data(), unsigned(n), sizeof(RTCRayHit));
        for (std::size_t k = 0; k < n; ++k) {
            const std::size_t i = first + k;
            const RTCRayHit& rh = stream[k];
            Hit1 h;  // as closest(): a miss leaves the hit untouched
            if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
                h = Hit1{rh.ray.tfar, rh.hit.u, rh.hit.v, rh.hit.primID, geometry_of(rh.hit)};
                reevaluate(ray_at(rays, i), h);
            }
            hits.t[i] = h.t;
            hits.u[i] = h.u;
            hits.v[i] = h.v;
            hits.prim[i] = h.prim;
            hits.geom[i] = h.geom;
        }
    }
}

void EmbreeAccel::occluded(const RayBatch& rays, std::vector<uint8_t>& occ, TraceCounters&) const {
    occ.resize(rays.size());
    thread_local std::vector<RTCRay> stream;
    // Debian's Embree 3.13 never returns from a coherent rtcOccluded1M over a scene with
    // instances on an AVX-512 Sapphire Rapids machine (seen 2026-11-26; the incoherent
    // stream and coherent rtcIntersect1M return). Such scenes' shadow batches go incoherent.
    RTCIntersectContext ctx = batch_context(rays.coherent && child_scenes_.empty());
    for (std::size_t first = 0; first < rays.size(); first += kStream) {
        const std::size_t n = std::min(kStream, rays.size() - first);
        stream.resize(n);
        for (std::size_t k = 0; k < n; ++k) fill_ray(rays, first + k, stream[k]);
        rtcOccluded1M(rtc_scene_, &ctx, stream.data(), unsigned(n), sizeof(RTCRay));
        for (std::size_t k = 0; k < n; ++k) occ[first + k] = stream[k].tfar == -kInfinity;
    }
}

}  // namespace foton
