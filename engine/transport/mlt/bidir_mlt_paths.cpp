// MLT over bidirectional paths: a vector is a camera subpath (its film position and lens,
// then its numbers) and a light subpath, their numbers interleaved (vcm_context.h), traced by
// the bdpt integrator's own subpath code with every strategy between them. The camera path's
// estimate lands on its pixel; each join of the light path to the camera on the pixel it
// reaches, scaled from bdpt's "one of N light paths" (N the image's pixels, which its MIS
// weights assume) to one sample of the film.
#include <algorithm>
#include <cmath>

#include "engine/core/error.h"
#include "engine/scene/light_set.h"
#include "engine/transport/bidir/camera_subpaths.h"
#include "engine/transport/bidir/light_subpaths.h"
#include "engine/transport/common/film_splats.h"
#include "mlt_paths.h"

namespace foton {

namespace {

struct BidirScratch : MltScratch {
    LightSubpathWorkspace light;
    CameraSubpathWorkspace camera;
    LightPathStore store;
    std::vector<Splat> splats;
    std::vector<uint32_t> splat_paths;
    std::vector<RGB> radiance;
    std::vector<std::vector<uint32_t>> joins_of;  // per path: its splats
};

class BidirMltPaths : public MltPaths {
  public:
    explicit BidirMltPaths(const RenderContext& ctx)
        : ctx_(ctx),
          lights_(ctx.scene, LightSelection::Power, ctx.settings.projection_maps),
          kernels_(kernel_materials(ctx.scene)),
          vcm_{ctx.scene, ctx.settings, ctx.accel,    lights_, ctx.seed,        9, 0, 0, 0, 1,
               0,         0.f,          VcmWeights{}, nullptr, StrategyLayers{}} {
        const Scene& scene = ctx.scene;
        if (scene.camera.type != CameraType::Perspective)
            throw InputError(scene.source, 0,
                             "mlt_paths=\"bdpt\" needs a perspective camera (light subpaths are "
                             "joined to the camera)");
        if (lights_.empty()) throw InputError(scene.source, 0, "mlt_paths=\"bdpt\" needs a light");
        if (scene.environment && scene.environment->has_portal())
            throw InputError(scene.source, 0,
                             "mlt_paths=\"bdpt\" does not weigh an environment light with a "
                             "portal: use mlt_paths=\"path\"");
        // bdpt's weights for an image of N light paths (vcm_render.cpp's first iteration).
        const float n = float(scene.film.full_pixels());
        vcm_.max_segments = ctx.settings.max_depth + 1;
        vcm_.light_paths = uint32_t(scene.film.full_pixels());
        VcmWeights& w = vcm_.weights;
        w.connect = true;
        w.merge = false;
        w.beta = ctx.settings.mis == MisHeuristic::Balance ? 1.f : ctx.settings.mis_beta;
        const float r = ctx.settings.photon.initial_radius > 0.f
                            ? ctx.settings.photon.initial_radius
                            : 0.005f * lights_.scene_radius();
        vcm_.radius = r;
        w.vc_weight = w.mis(1.f / (kPi * r * r * n));
        kernels_.enabled = ctx.settings.simd_shading;
        vcm_.kernels = &kernels_;
        // A light path's join, one of N, is 1 / N of a pixel sample of its pixel; a vector is
        // a sample of the whole film (its pixels', widened by the filter's reach).
        join_scale_ = float(double(n) / FilmDomain(scene.film).area());
    }
    uint32_t dims() const override {
        // Camera numbers: 8 per bounce; light numbers: 8 to start and 6 per bounce.
        return kPrimaryBidirStart + 2 * 8 * (ctx_.settings.max_depth + 3);
    }
    std::unique_ptr<MltScratch> make_scratch() const override {
        return std::make_unique<BidirScratch>();
    }

    void evaluate(MltBatch& b, MltScratch& base) const override {
        BidirScratch& s = static_cast<BidirScratch&>(base);
        const uint32_t n = uint32_t(b.size());
        VcmContext c = vcm_;
        c.primary = b.v.data();
        s.store.vertices.clear();
        s.splats.clear();
        s.splat_paths.clear();
        trace_light_subpaths(c, 0, n, s.light, s.store.vertices, s.splats, &s.splat_paths, s.stats);
        // Where each path's vertices begin (they are in path order).
        const LightVertices& lv = s.store.vertices;
        s.store.first.assign(std::size_t(n) + 1, uint32_t(lv.size()));
        for (std::size_t i = lv.size(); i-- > 0;) s.store.first[lv.path[i]] = uint32_t(i);
        for (uint32_t p = n; p-- > 0;)
            s.store.first[p] = std::min(s.store.first[p], s.store.first[p + 1]);
        trace_camera_subpaths(c, s.store, 0, n, s.camera, s.radiance, nullptr, s.stats);
        s.joins_of.resize(n);
        for (auto& j : s.joins_of) j.clear();
        for (uint32_t k = 0; k < uint32_t(s.splats.size()); ++k)
            s.joins_of[s.splat_paths[k]].push_back(k);
        const FilmSettings& film = ctx_.scene.film;
        const FilmDomain domain(film);
        b.clear_results();
        for (uint32_t i = 0; i < n; ++i) {
            PrimaryVector& v = *b.v[i];
            const FilmPoint at = domain.at(film, v.get(0), v.get(1));
            const RGB& L = s.radiance[i];
            if (L.is_finite() && !L.is_black())
                film.spread(at.x, at.y, [&](uint32_t pixel, float w) {
                    b.contrib.push_back({pixel, L * w});
                });
            for (const uint32_t k : s.joins_of[i]) {
                const RGB value = s.splats[k].value * join_scale_;
                if (value.is_finite() && !value.is_black())
                    b.contrib.push_back({s.splats[k].pixel, value});
            }
            b.close(i);
        }
    }

  private:
    const RenderContext& ctx_;
    const LightSet lights_;
    KernelMaterials kernels_;
    VcmContext vcm_;
    float join_scale_ = 1.f;
};

}  // namespace

std::unique_ptr<MltPaths> make_bidir_mlt_paths(const RenderContext& ctx) {
    return std::make_unique<BidirMltPaths>(ctx);
}

}  // namespace foton
