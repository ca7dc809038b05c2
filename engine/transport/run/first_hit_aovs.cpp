#include "first_hit_aovs.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <tbb/parallel_for.h>

#include "camera_tile.h"
#include "engine/core/rng.h"
#include "engine/core/rng_streams.h"
#include "engine/core/thread_pinning.h"
#include "engine/core/warp.h"
#include "engine/transport/common/camera_integrator.h"
#include "engine/transport/common/surface.h"

namespace foton {

namespace {

// A pixel's running sums: albedo over every sample, the geometric quantities over the hits.
struct FirstHitSums {
    RGB albedo{0.f};
    Vec3 n{0, 0, 0}, ns{0, 0, 0}, p{0, 0, 0};
    float z = 0.f;
    uint32_t hits = 0;
};

// The BSDF's directional albedo towards wo (pbrt's rho): the mean of f |cos| / pdf over
// kAlbedoSamples samples, stratified 4 x 4 in direction and 16-fold in the lobe choice, both
// shifted by one random offset of the pixel sample. Delta lobes count through their sampled
// weight; for a lone Lambert lobe every sample is its reflectance, so the estimate is exact.
RGB directional_albedo(const Bsdf& bsdf, const Vec3& wo, const BsdfContext& ctx, uint64_t seed,
                       uint64_t id) {
    const float r0 = rng::uniform(seed, kAovStream, id, 0);
    const float r1 = rng::uniform(seed, kAovStream, id, 1);
    const float r2 = rng::uniform(seed, kAovStream, id, 2);
    RGB sum{0.f};
    for (int k = 0; k < kAlbedoSamples; ++k) {
        const float uc = std::min((float(k) + r0) / kAlbedoSamples, 0.99999994f);
        // The direction strata go through the lobe strata in another order (k * 5 mod 16),
        // so a lobe chosen by a range of k still sees directions from every row.
        const int d = (k * 5) % kAlbedoSamples;
        const Point2 u{std::min((float(d % 4) + r1) / 4.f, 0.99999994f),
                       std::min((float(d / 4) + r2) / 4.f, 0.99999994f)};
        BsdfSample s;
        if (!bsdf.sample(wo, uc, u, ctx, s) || !(s.pdf > 0.f)) continue;
        sum += s.f * (std::abs(s.wi.z) / s.pdf);
    }
    return sum * (1.f / float(kAlbedoSamples));
}

// World vector v in camera space (Camera::world_to_camera's axes).
Vec3 to_camera(const Camera& c, const Vec3& v) {
    return {dot(v, c.u), dot(v, c.v), dot(v, c.w)};
}

// One image row: its samples' camera rays (those of the render's first pass), traced in one
// batch, each hit's quantities added to its pixel.
void trace_row(const Scene& scene, const RenderSettings& settings, const Intersector& accel,
               uint64_t seed, uint32_t spp, int y, FirstHitSums* row) {
    std::vector<SampleJob> jobs;
    jobs.reserve(std::size_t(scene.film.width) * spp);
    append_pass_jobs(scene.film, {0, y, scene.film.width, y + 1}, 0, 0, spp, spp, jobs);
    RayBatch rays;
    generate_camera_rays(scene, settings.sampler, jobs, seed, rays);
    HitBatch hits;
    TraceCounters counters;
    accel.intersect(rays, hits, counters);
    const Camera& cam = scene.camera;
    for (std::size_t i = 0; i < jobs.size(); ++i) {
        FirstHitSums& px = row[jobs[i].x];
        if (hits.geom[i] == kNoHit) continue;
        const SurfacePoint sp = surface_at(scene, rays, hits, i);
        std::optional<Material> scratch;
        const Material& m = scene.material_at(hits.geom[i], sp.tex(), scratch);
        const warp::Frame frame = sp.frame();
        const BsdfContext ctx{sp.front_face, Transport::Radiance};
        px.albedo +=
            directional_albedo(m.bsdf, frame.to_local(-rays.direction(i)), ctx, seed, jobs[i].id);
        const Vec3 p = to_camera(cam, sp.p - cam.eye);
        px.n = px.n + to_camera(cam, sp.ng);
        px.ns = px.ns + to_camera(cam, sp.ns);
        px.p = px.p + p;
        px.z += p.z;
        ++px.hits;
    }
}

}  // namespace

std::vector<AovLayer> render_first_hit_aovs(const Scene& scene, const RenderSettings& settings,
                                            const Intersector& accel, const RenderOptions& opt) {
    const uint32_t bits = settings.aovs & kAovFirstHit;
    if (!bits) return {};
    const int width = scene.film.width, height = scene.film.height;
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    const uint32_t spp = std::clamp<uint32_t>(opt.spp, 1, kFirstHitSpp);
    std::vector<FirstHitSums> sums(pixels);
    PinnedArena arena(resolve_threads(opt.threads));
    arena.execute([&] {
        tbb::parallel_for(0, height, [&](int y) {
            trace_row(scene, settings, accel, opt.seed, spp, y,
                      &sums[std::size_t(y) * std::size_t(width)]);
        });
    });

    std::vector<AovLayer> layers;
    auto layer = [&](uint32_t bit, auto&& value) {
        if (!(bits & bit)) return;
        AovLayer l{aov_names().name(bit), aov_channels(bit), {}};
        l.values.resize(pixels * l.stride());
        for (std::size_t i = 0; i < pixels; ++i) value(sums[i], &l.values[i * l.stride()]);
        layers.push_back(std::move(l));
    };
    const float inv_spp = 1.f / float(spp);
    auto mean = [](const FirstHitSums& s, const Vec3& v, float* out) {
        const float k = s.hits ? 1.f / float(s.hits) : 0.f;
        out[0] = v.x * k, out[1] = v.y * k, out[2] = v.z * k;
    };
    layer(kAovAlbedo, [&](const FirstHitSums& s, float* out) {
        out[0] = s.albedo.r * inv_spp, out[1] = s.albedo.g * inv_spp, out[2] = s.albedo.b * inv_spp;
    });
    layer(kAovNormal, [&](const FirstHitSums& s, float* out) {
        mean(s, s.n, out);
        mean(s, s.ns, out + 3);
    });
    layer(kAovDepth, [&](const FirstHitSums& s, float* out) {
        out[0] = s.hits ? s.z / float(s.hits) : INFINITY;
    });
    layer(kAovPosition, [&](const FirstHitSums& s, float* out) { mean(s, s.p, out); });
    return layers;
}

}  // namespace foton
