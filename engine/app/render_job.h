#pragma once
// A render job as every front-end makes it (`foton render`, `foton serve`, `foton scale`): the
// scene with the user's settings on top, checked by the same parsers and limits whichever tool
// took them; and what they write about the render they ran (pbrt-v4's standard attributes and
// foton's), so an image says how it was made whichever tool made it.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/film/image_io.h"
#include "engine/scene/scene.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/render.h"
#include "image_flags.h"

namespace foton::app {

// What the user asked for beyond the scene file, as text: the settings' own parsers check
// every value, so the command line and the web page accept the same values and fail with the
// same messages.
struct JobRequest {
    std::string scene;      // the scene file
    RendererOverrides set;  // key=value renderer settings (--set, the page's settings box)
    std::string accel;      // "" = the scene's <aggregate>
    ImageFlags image;       // resolution and crop, checked against the image limits
    // Renderer settings given as flags: {key, value, flag}, after `set`; a bad value is
    // reported under the flag's name.
    std::vector<std::array<std::string, 3>> flags;
    std::optional<std::string> spp;     // per pass, or the adaptive pilot
    std::optional<std::string> passes;  // progressive passes
    std::optional<float> time;          // seconds of progressive passes
    // What the three above are called in messages: the command line's flags, or the Python
    // module's keywords.
    struct Names {
        std::string spp = "--spp", passes = "--passes", time = "--time";
    } names;
};

struct RenderJob {
    Scene scene;
    RenderSettings settings;
    RenderOptions options;
    bool progressive = false;  // --passes or --time: passes of one sample unless --spp
};

// Loads and checks everything; InputError at the first problem. The settings are read once.
RenderJob make_job(const JobRequest& request);
// The same for a scene loaded before (with `request.set` applied then): the Python module loads
// a scene once and renders it with many settings.
RenderJob configure_job(Scene loaded, const JobRequest& request);

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
// How the samples spread over the pixels.
struct SampleSpread {
    uint32_t fewest = 0, most = 0;
    std::size_t none = 0;  // pixels no sample reached
    bool uneven() const { return fewest != most; }
};
// Where pixels average different sample counts (adaptive sampling, a pass cut short by a
// stop): the EXR gets every pixel's count as its `samples` channel and, when some pixels got
// none, `foton:unfinishedPixels`; with the samples AOV asked for (`aovs`, film/aov.h's bits),
// whatever the spread. The result's AOV layers go to `info.layers` too. `info` points into
// `result`.
SampleSpread describe_sample_counts(const RenderResult& result, ImageAttributes& attrs,
                                    ExrRenderInfo& info, uint32_t aovs);

}  // namespace foton::app
