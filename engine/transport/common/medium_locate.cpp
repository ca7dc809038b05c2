#include "medium_locate.h"

#include "engine/core/error.h"
#include "engine/core/stats.h"
#include "medium_shadow.h"
#include "surface.h"

namespace foton {

namespace {
// Surfaces the walk passes at most: only a degenerate scene has more between camera and point.
constexpr int kMaxSurfaces = 4096;
}  // namespace

int32_t locate_medium(const Scene& scene, const Intersector& accel, const Vec3& p) {
    int32_t medium = scene.camera_medium;
    if (scene.media.empty()) return medium;
    Vec3 o = scene.camera.eye;
    const Vec3 to = p - o;
    const float len = length(to);
    if (!(len > 0.f)) return medium;
    const Vec3 d = to / len;
    RayBatch ray;
    HitBatch hit;
    TraceCounters counters;
    for (int k = 0; k < kMaxSurfaces; ++k) {
        const float rest = dot(p - o, d);
        if (!(rest > 0.f)) break;
        ray.clear();
        ray.push(o, d, 0.f, rest, 0);
        accel.intersect(ray, hit, counters);
        if (hit.geom[0] == kNoHit) break;
        const SurfacePoint sp = surface_at(scene, ray, hit, 0);
        medium = medium_after(scene, hit.geom[0], sp, d, medium);
        o = offset_origin(sp, d);
    }
    return medium;
}

std::vector<int32_t> light_media(const Scene& scene, const Intersector& accel,
                                 const LightSet& lights) {
    std::vector<int32_t> media;
    for (std::size_t i = 0; i < lights.size(); ++i) {
        EmissionSample es;
        int32_t m = scene.camera_medium;
        if (lights.sample_le(uint32_t(i), {0.5f, 0.5f}, {0.5f, 0.5f}, 0.5f, es))
            m = locate_medium(
                scene, accel,
                es.n == Vec3{} ? es.p : es.p + es.dir * 1e-3f * lights.scene_radius());
        media.push_back(m);
    }
    return media;
}

void refuse_emitting_media(const Scene& scene, const std::string& why) {
    for (const Medium& m : scene.media)
        if (m.emits())
            throw InputError(m.file, m.line, "medium '" + m.name + "' emits, and " + why);
}

}  // namespace foton
