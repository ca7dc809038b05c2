// MLT over the path tracer's paths: a vector is the film position (2), the lens (2), then the
// numbers the path tracer draws per bounce (path_sampler.h's `primary` kind).
#include <algorithm>

#include "engine/transport/common/film_splats.h"
#include "engine/transport/common/path_sampler.h"
#include "engine/transport/path/path.h"
#include "mlt_paths.h"

namespace foton {

namespace {

struct PathScratch : MltScratch {
    std::unique_ptr<IntegratorWorkspace> ws;
    RayBatch rays;
    std::vector<PathSampler> samplers;
    std::vector<uint64_t> keys;
    std::vector<RGB> radiance;
    std::vector<FilmPoint> at;  // each vector's film position
};

class PathMltPaths : public MltPaths {
  public:
    explicit PathMltPaths(const RenderContext& ctx)
        : ctx_(ctx), path_(ctx, VertexRules::path(ctx.settings)) {}
    uint32_t dims() const override {
        return 4 + (ctx_.settings.max_depth + 1) * kPathDimsPerBounce;
    }
    std::unique_ptr<MltScratch> make_scratch() const override {
        auto s = std::make_unique<PathScratch>();
        s->ws = path_.make_workspace();
        return s;
    }

    void evaluate(MltBatch& b, MltScratch& base) const override {
        PathScratch& s = static_cast<PathScratch&>(base);
        const FilmSettings& film = ctx_.scene.film;
        const std::size_t n = b.size();
        s.rays.clear();
        s.samplers.resize(n);
        s.at.resize(n);
        s.keys.assign(b.keys.begin(), b.keys.begin() + std::ptrdiff_t(n));
        const FilmDomain domain(film);
        for (std::size_t i = 0; i < n; ++i) {
            PrimaryVector& v = *b.v[i];
            s.at[i] = domain.at(film, v.get(0), v.get(1));
            Vec3 o, d;
            ctx_.scene.camera.generate(s.at[i].x, s.at[i].y, {v.get(2), v.get(3)}, o, d);
            s.rays.push(o, d, 0.f, kInfinity, uint32_t(i));
            s.samplers[i] = PathSampler::primary(&v, 4, s.keys[i], ctx_.seed);
        }
        path_.trace_camera_paths(s.rays, s.samplers, s.keys, *s.ws, s.radiance, s.stats);
        b.clear_results();
        for (std::size_t i = 0; i < n; ++i) {
            const RGB& L = s.radiance[i];
            if (L.is_finite() && !L.is_black())
                film.spread(s.at[i].x, s.at[i].y, [&](uint32_t pixel, float w) {
                    b.contrib.push_back({pixel, L * w});
                });
            b.close(i);
        }
    }

  private:
    const RenderContext& ctx_;
    const PathIntegrator path_;
};

}  // namespace

std::unique_ptr<MltPaths> make_path_mlt_paths(const RenderContext& ctx) {
    return std::make_unique<PathMltPaths>(ctx);
}

}  // namespace foton
