#pragma once
// What the tile driver (driver/camera_driver.h) asks of an integrator that starts its paths at the
// camera (raytracer, path, distributed): the radiance of a list of pixel samples. The driver
// decides which samples (fixed count, progressive passes, adaptive rounds) and accumulates
// them; the integrator traces them as a wavefront of ray batches.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "engine/core/ray_batch.h"
#include "engine/core/rgb.h"
#include "engine/core/rng.h"
#include "engine/core/rng_streams.h"
#include "engine/core/sampler.h"
#include "engine/core/sobol.h"
#include "engine/core/stats.h"
#include "engine/core/zsobol.h"
#include "engine/scene/scene.h"

namespace foton {

// One pixel sample: the film position comes from point `pat_i` of a `pat_n`-point pattern
// (the scene's sampler) keyed by (pixel, pat_round); `id` keys every other random number of
// the sample and is unique in the image.
struct SampleJob {
    uint32_t x = 0, y = 0;
    uint32_t pat_i = 0, pat_n = 1, pat_round = 0;
    uint64_t id = 0;
};

// What keys a pixel's pattern in a round (and, with the Sobol' sampler, every dimension
// pair of its paths).
inline uint64_t pixel_pattern_key(const Scene& scene, const SampleJob& j) {
    return rng::hash(kPixelStream, scene.film.pixel_id(j.x, j.y), j.pat_round, 0);
}

// With sampler="zsobol": the sample's index in the image-wide sequence, from its pixel's place
// in the full image.
inline zsobol::Index zsobol_index(const Scene& scene, const SampleJob& j, uint64_t seed) {
    const FilmSettings& f = scene.film;
    return zsobol::index_of(j.x + uint32_t(f.x0), j.y + uint32_t(f.y0), uint32_t(f.full_width),
                            uint32_t(f.full_height), j.pat_i, j.pat_n, seed, j.pat_round);
}

inline Point2 pixel_sample(const Scene& scene, SamplerKind sampler, const SampleJob& j,
                           uint64_t seed) {
    if (sampler == SamplerKind::ZSobol) {
        Point2 p;
        zsobol::sample2(zsobol_index(scene, j, seed), 0, p.x, p.y);
        return p;
    }
    return sample_pattern(sampler, j.pat_i, j.pat_n, seed, pixel_pattern_key(scene, j));
}

// The pixel positions of `jobs` as a table (x in [0, n), y in [n, 2n) of `table`, n the
// jobs' count rounded up to 16) when the sampler is Sobol' or Z-Sobol'; false (and nothing
// written) for the others.
inline bool pixel_sample_table(const Scene& scene, SamplerKind sampler,
                               const std::vector<SampleJob>& jobs, uint64_t seed,
                               std::vector<float>& table) {
    if (sampler != SamplerKind::Sobol && sampler != SamplerKind::ZSobol) return false;
    // A sample's Sobol' index (or Z-Sobol' bit count), count and key, padded with one-point
    // patterns up to the kernels' 16.
    thread_local std::vector<uint64_t> key, z_index;
    thread_local std::vector<uint32_t> index, count;
    const std::size_t n = (jobs.size() + 15) / 16 * 16;
    key.assign(n, 0);
    index.assign(n, 0);
    count.assign(n, 1);
    table.resize(2 * n);
    const uint32_t pair = 0;
    if (sampler == SamplerKind::Sobol) {
        for (std::size_t s = 0; s < jobs.size(); ++s) {
            index[s] = jobs[s].pat_i;
            count[s] = jobs[s].pat_n;
            key[s] = pixel_pattern_key(scene, jobs[s]);
        }
        kern::sobol::sample_table(seed, index.data(), count.data(), key.data(), jobs.size(), &pair,
                                  1, table.data(), n);
    } else {
        z_index.assign(n, 0);
        for (std::size_t s = 0; s < jobs.size(); ++s) {
            const zsobol::Index z = zsobol_index(scene, jobs[s], seed);
            z_index[s] = z.index;
            index[s] = z.bits;
            key[s] = z.key;
        }
        kern::zsobol::sample_table(z_index.data(), index.data(), key.data(), jobs.size(), &pair, 1,
                                   table.data(), n);
    }
    return true;
}

// Appends the camera rays of `jobs` to `rays` (slot = job index): the pixel position from
// the renderer's sampler, the thin-lens position from the job's own stream.
inline void generate_camera_rays(const Scene& scene, SamplerKind sampler,
                                 const std::vector<SampleJob>& jobs, uint64_t seed,
                                 RayBatch& rays) {
    rays.reserve(rays.size() + jobs.size());
    // A tile's jobs are its pixels in rows, each pixel's samples together: neighbours in the
    // batch are neighbours on the film.
    rays.coherent = rays.empty();
    // Sobol' and Z-Sobol' pixel positions come as one table (the same numbers as
    // pixel_sample's, drawn by the kernels 8 samples at a time).
    thread_local std::vector<float> table;
    const bool tabled = pixel_sample_table(scene, sampler, jobs, seed, table);
    const std::size_t stride = table.size() / 2;
    for (uint32_t slot = 0; slot < jobs.size(); ++slot) {
        const SampleJob& j = jobs[slot];
        // The sampler's point in the pixel, moved by the pixel filter's importance.
        const Point2 px =
            scene.film.filter.pixel_position(tabled ? Point2{table[slot], table[stride + slot]}
                                                    : pixel_sample(scene, sampler, j, seed));
        const Point2 lens = {rng::uniform(seed, kLensStream, j.id, 0),
                             rng::uniform(seed, kLensStream, j.id, 1)};
        Vec3 o, d;
        // Image position: the film's pixel plus a crop window's offset, as integers first.
        scene.camera.generate(float(int(j.x) + scene.film.x0) + px.x,
                              float(int(j.y) + scene.film.y0) + px.y, lens, o, d);
        rays.push(o, d, 0.f, kInfinity, slot);
    }
}

// With a pixel filter that is negative in places (PixelFilter::negative_lobes), each camera
// sample's filter weight, by slot, into w (the positions generate_camera_rays gives the same
// jobs); false, w untouched, when every weight is 1.
inline bool camera_sample_weights(const Scene& scene, SamplerKind sampler,
                                  const std::vector<SampleJob>& jobs, uint64_t seed,
                                  std::vector<float>& w) {
    const PixelFilter& filter = scene.film.filter;
    if (!filter.negative_lobes()) return false;
    thread_local std::vector<float> table;
    const bool tabled = pixel_sample_table(scene, sampler, jobs, seed, table);
    const std::size_t stride = table.size() / 2;
    w.resize(jobs.size());
    for (uint32_t slot = 0; slot < jobs.size(); ++slot)
        w[slot] = filter.sample_weight(
            filter.pixel_position(tabled ? Point2{table[slot], table[stride + slot]}
                                         : pixel_sample(scene, sampler, jobs[slot], seed)));
    return true;
}

struct CacheWorkspace;

// Per-thread scratch of an integrator, reused from tile to tile.
struct IntegratorWorkspace {
    virtual ~IntegratorWorkspace() = default;
    // The components AOV: part c of sample i's estimate at parts[i * part_count + c] (sized by
    // the driver before the first phase; part_count 0: not asked for).
    std::vector<RGB> parts;
    uint32_t part_count = 0;
    void add_part(uint32_t slot, uint32_t c, const RGB& v) {
        if (part_count) parts[std::size_t(slot) * part_count + c] += v;
    }
    // What `step` adds to `radiance`, as part c (a step that adds to radiance in code shared
    // with other integrators: a shadow batch, the cache's lookups).
    template <class Step>
    void as_part(uint32_t c, std::vector<RGB>& radiance, Step&& step) {
        if (!part_count) return step();
        const std::vector<RGB> before = radiance;
        step();
        for (std::size_t i = 0; i < radiance.size(); ++i)
            parts[i * part_count + c] += radiance[i] - before[i];
    }
    // The irradiance cache's part (its new records), if the integrator uses one.
    virtual CacheWorkspace* cache_workspace() { return nullptr; }
};

class CameraIntegrator {
  public:
    virtual ~CameraIntegrator() = default;
    virtual std::unique_ptr<IntegratorWorkspace> make_workspace() const = 0;
    // The phases a list of samples goes through, each a node of the render's stage graph
    // that tiles stream through: most integrators trace their camera paths in one; the
    // photon mapper's camera gather (to the visible points) and final gather are two.
    virtual uint32_t phases() const { return 1; }
    // The parts of its estimate it can also write apart (the components AOV), which add up to
    // it; none by default.
    virtual std::vector<std::string> components() const { return {}; }
    virtual const char* phase_name(uint32_t) const { return "camera-paths"; }
    // Phase `phase` of the samples `jobs`: phase 0 starts them (radiance is resized to
    // jobs.size()), and after the last, radiance[i] is the estimate of jobs[i]. The
    // workspace carries the samples' state from one phase to the next.
    virtual void trace_phase(uint32_t phase, const std::vector<SampleJob>& jobs,
                             IntegratorWorkspace& ws, std::vector<RGB>& radiance,
                             RenderStats& stats) const = 0;
    // Every phase in turn.
    void trace(const std::vector<SampleJob>& jobs, IntegratorWorkspace& ws,
               std::vector<RGB>& radiance, RenderStats& stats) const {
        for (uint32_t p = 0; p < phases(); ++p) trace_phase(p, jobs, ws, radiance, stats);
    }
};

}  // namespace foton
