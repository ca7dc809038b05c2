#pragma once
// What every front-end writes about a render it ran: `foton render` (its image and snapshots)
// and `foton serve` (the EXR the page saves) record the same attributes, pbrt-v4's standard
// ones and foton's, from one place, so an image says how it was made whichever tool made it.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/film/image_io.h"
#include "engine/scene/scene.h"
#include "engine/transport/registry/render.h"

namespace foton::app {

// The request as the tool saw it.
struct JobRecord {
    std::string scene_path;
    std::string command_line;  // as typed, or the web page's request in the same words
};

// foton's attributes: scene, integrator (with the path tracer's MIS), samples a pixel averages,
// passes, seed, seconds, accelerator, version, commit, command line, every renderer setting as
// used.
ImageAttributes job_attributes(const JobRecord& job, const Scene& scene, const RenderSettings& rs,
                               const RenderOptions& opt, double seconds, uint32_t passes,
                               double spp, const char* accel_name);
// pbrt-v4's standard attributes: render time, samples, the camera's matrices, and the crop as
// the data window of the full image.
ExrRenderInfo job_exr_info(const Scene& scene, double seconds, double spp);
// What a pixel's value averages, over the image: the mean of samples_per_pixel.
double mean_samples(const RenderResult& result);

}  // namespace foton::app
