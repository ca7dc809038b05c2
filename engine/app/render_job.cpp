#include "render_job.h"

#include <algorithm>
#include <cstdint>

#include <cmath>
#include <cstdio>

#include "build_info.h"
#include "engine/core/error.h"
#include "engine/core/params.h"
#include "engine/transport/common/mis.h"
#include "scene_flags.h"

namespace foton::app {

namespace {
// Shortest decimal form (%.6g): 16, 24.5.
std::string format_number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}
}  // namespace

RenderJob make_job(const JobRequest& r) {
    return configure_job(load_scene(r.scene, r.set), r);
}

RenderJob configure_job(Scene loaded, const JobRequest& r) {
    RenderJob job;
    Scene& scene = job.scene;
    scene = std::move(loaded);
    apply_accel_flag(r.accel, scene);
    apply_image_flags(r.image, scene);
    for (const auto& [key, value, flag] : r.flags) scene.renderer.set(key, value, flag, 0);
    // --spp: the samples per pixel (per pass), or under adaptive sampling the pilot. Whether
    // adaptive sampling is on is read off the settings first (the same parser, so the same
    // message for a bad value), so that the settings are parsed once.
    if (r.spp) {
        const bool adaptive = scene.renderer.boolean("adaptive", false);
        scene.renderer.set(adaptive ? "adaptive_pilot" : "spp", *r.spp, r.names.spp, 0);
    }
    job.settings = render_settings(scene);
    // Settings for another integrator, ignored: said with the scene's own warnings.
    scene.warnings.insert(scene.warnings.end(), job.settings.warnings.begin(),
                          job.settings.warnings.end());
    RenderOptions& opt = job.options;
    opt = job.settings.run;
    if (r.time) {
        if (!(*r.time >= 0.f) || !std::isfinite(*r.time))
            throw InputError(r.names.time, 0, "must be a number of seconds, not negative");
        opt.time_limit = *r.time;
    }
    if (r.passes)
        opt.max_passes =
            uint32_t(integer_or_fail(*r.passes, 1, kMaxPasses, r.names.passes, 0, "the value"));
    job.progressive = opt.time_limit > 0.f || r.passes;
    if (job.progressive && job.settings.adaptive.enabled)
        throw InputError(opt.time_limit > 0.f ? r.names.time : r.names.passes, 0,
                         "progressive passes and adaptive sampling do not mix");
    // Progressive passes are one sample per pixel each unless --spp sets the pass size.
    if (job.progressive && !r.spp) opt.spp = 1;
    return job;
}

ImageAttributes job_attributes(const JobRecord& job, const Scene& scene, const RenderSettings& rs,
                               const RenderOptions& opt, double seconds, uint32_t passes,
                               double spp, const char* accel_name) {
    char secs[32];
    std::snprintf(secs, sizeof secs, "%.3f", seconds);
    std::string method = rs.integrator;
    if (rs.integrator == "path")
        method += rs.nee ? std::string(" nee mis=") + mis_name(rs.mis) +
                               (rs.mis == MisHeuristic::Power && rs.mis_beta != 2.f
                                    ? " beta=" + format_number(rs.mis_beta)
                                    : std::string())
                         : " bsdf-only";
    return ImageAttributes{
        {"foton:scene", job.scene_path},
        {"foton:integrator", method},
        // What a pixel's value averages: the mean over pixels for adaptive sampling, the
        // passes for SPPM, spp x passes otherwise.
        {"foton:samples", format_number(spp)},
        {"foton:passes", std::to_string(passes)},
        {"foton:seed", std::to_string(opt.seed)},
        {"foton:renderSeconds", secs},
        {"foton:accel", accel_name},
        {"foton:version", FOTON_VERSION},
        {"foton:gitCommit", git_commit()},
        {"foton:commandLine", job.command_line},
        {"foton:settings", settings_text(scene)},
    };
}

ExrRenderInfo job_exr_info(const Scene& scene, double seconds, double spp) {
    // samplesPerPixel is an integer (pbrt-v4's): written only when the samples are a whole
    // number per pixel, never a rounded mean (3.625 once became 4); foton:samples has the
    // exact mean either way.
    const bool whole = spp == std::floor(spp) && spp <= double(INT32_MAX);
    ExrRenderInfo info;
    info.render_seconds = float(seconds);
    info.samples_per_pixel = whole ? int(spp) : -1;
    info.world_to_camera = scene.camera.world_to_camera();
    // Panoramic cameras have no normalised device coordinates (no projection).
    if (!scene.camera.panoramic()) info.world_to_ndc = scene.camera.world_to_ndc();
    info.x0 = scene.film.x0;
    info.y0 = scene.film.y0;
    info.display_width = scene.film.full_width;
    info.display_height = scene.film.full_height;
    return info;
}

double mean_samples(const RenderResult& result) {
    double sum = 0.0;
    for (uint32_t c : result.samples_per_pixel) sum += c;
    return result.samples_per_pixel.empty() ? 0.0 : sum / double(result.samples_per_pixel.size());
}

SampleSpread describe_sample_counts(const RenderResult& result, ImageAttributes& attrs,
                                    ExrRenderInfo& info, uint32_t aovs) {
    if (!result.aovs.empty()) info.layers = &result.aovs;
    const std::vector<uint32_t>& counts = result.samples_per_pixel;
    if (counts.empty() || counts.size() != result.film.pixels.size()) return {};
    const auto [lo, hi] = std::minmax_element(counts.begin(), counts.end());
    SampleSpread spread{*lo, *hi, 0};
    if (aovs & kAovSamples) info.samples = &counts;
    if (!spread.uneven()) return spread;
    info.samples = &counts;
    spread.none = std::size_t(std::count(counts.begin(), counts.end(), 0u));
    if (spread.none) attrs.push_back({"foton:unfinishedPixels", std::to_string(spread.none)});
    return spread;
}

}  // namespace foton::app
