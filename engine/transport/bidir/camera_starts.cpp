#include "camera_starts.h"

#include <algorithm>

#include "engine/transport/common/camera_integrator.h"
#include "engine/transport/common/film_splats.h"

namespace foton {

void start_camera_rays(const VcmContext& c, uint32_t first, uint32_t count,
                       CameraSubpathWorkspace& ws) {
    const Scene& scene = c.scene;
    const FilmSettings& film = scene.film;
    ws.path.resize(count);
    if (c.primary) {
        const FilmDomain domain(film);
        for (uint32_t k = 0; k < count; ++k) {
            PrimaryVector& v = *c.primary[first + k];
            const FilmPoint at = domain.at(film, v.get(0), v.get(1));
            Vec3 o, d;
            scene.camera.generate(at.x, at.y, {v.get(2), v.get(3)}, o, d);
            ws.rays.push(o, d, 0.f, kInfinity, k);
            ws.path[k] = first + k;
        }
        return;
    }
    const uint32_t width = uint32_t(film.width);
    std::vector<SampleJob> jobs(count);
    const uint64_t npix = film.full_pixels();
    for (uint32_t k = 0; k < count; ++k) {
        const uint32_t pixel = first + k;
        SampleJob& j = jobs[k];
        j.x = pixel % width;
        j.y = pixel / width;
        ws.path[k] = uint32_t(film.pixel_id(j.x, j.y));
        j.pat_i = c.pass_sample;
        j.pat_n = c.pass_samples;
        j.pat_round = c.pass;
        j.id = c.iteration * npix + film.pixel_id(j.x, j.y);
    }
    generate_camera_rays(scene, c.settings.sampler, jobs, c.seed, ws.rays);
    // A filter with negative lobes weighs each camera sample (its subpath's throughput).
    thread_local std::vector<float> weight;
    if (camera_sample_weights(scene, c.settings.sampler, jobs, c.seed, weight))
        for (uint32_t k = 0; k < count; ++k) ws.beta[k] *= weight[k];
}

}  // namespace foton
