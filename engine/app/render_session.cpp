#include "render_session.h"

#include <unistd.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "convergence_log.h"
#include "engine/accel/intersector.h"
#include "engine/core/error.h"
#include "engine/film/image_io.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/render.h"
#include "render_job.h"

namespace foton::app {

RenderSession::~RenderSession() {
    stop();
    if (thread_.joinable()) thread_.join();
}

bool RenderSession::start(const SessionRequest& request, std::string& error) {
    std::lock_guard lock(mutex_);
    if (state_ == "running") {
        error = "a render is running; stop it first";
        return false;
    }
    if (thread_.joinable()) thread_.join();  // the previous render, finished
    cancel_ = false;
    state_ = "running";
    message_.clear();
    stats_table_.clear();
    image_.reset();
    ++image_version_;
    exr_.reset();
    aovs_.reset();
    convergence_.clear();
    passes_ = 0;
    seconds_ = spp_ = rays_per_second_ = 0.0;
    scene_name_ = std::filesystem::path(request.scene_path).filename().string();
    thread_ = std::thread([this, request] { run(request); });
    return true;
}

void RenderSession::stop() {
    cancel_ = true;
}

namespace {
// The page's request in the command line's words, for the image's foton:commandLine.
std::string request_text(const SessionRequest& r) {
    std::string s = "foton serve: render " + r.scene_path;
    if (!r.integrator.empty()) s += " --integrator " + r.integrator;
    if (!r.accel.empty()) s += " --accel " + r.accel;
    if (r.width > 0) s += " --width " + std::to_string(r.width);
    if (r.height > 0) s += " --height " + std::to_string(r.height);
    s += " --spp " + std::to_string(r.spp) + " --seed " + std::to_string(r.seed) + " --threads " +
         std::to_string(r.threads);
    if (r.passes > 0) s += " --passes " + std::to_string(r.passes);
    if (r.time > 0.f) s += " --time " + std::to_string(r.time);
    if (!r.reference_path.empty()) s += " --reference " + r.reference_path;
    for (const auto& [key, value] : r.set) s += " --set " + key + "=" + value;
    return s;
}
}  // namespace

void RenderSession::run(SessionRequest req) {
    try {
        // The page's request goes through the command line's job: the same parsers, limits
        // and messages.
        JobRequest request{req.scene_path,
                           RendererOverrides(req.set.begin(), req.set.end()),
                           req.accel,
                           {},
                           {},
                           std::to_string(req.spp),
                           {},
                           {},
                           {}};
        if (req.width > 0) request.image.width = std::to_string(req.width);
        if (req.height > 0) request.image.height = std::to_string(req.height);
        if (!req.integrator.empty())
            request.flags.push_back({"type", req.integrator, "integrator"});
        request.flags.push_back({"seed", std::to_string(req.seed), "seed"});
        request.flags.push_back({"num_threads", std::to_string(req.threads), "threads"});
        if (req.passes > 0) request.passes = std::to_string(req.passes);
        if (req.time != 0.f) request.time = req.time;  // NaN and negative times are refused
        RenderJob job = make_job(request);
        const Scene& scene = job.scene;
        const RenderSettings& rs = job.settings;
        RenderOptions& opt = job.options;
        opt.progress = &progress_;
        opt.cancel = &cancel_;
        std::unique_ptr<ConvergenceLog> convergence;
        if (!req.reference_path.empty())
            convergence =
                std::make_unique<ConvergenceLog>(req.reference_path, scene.film, req.exclude_above);
        opt.on_pass = [&](const Film& film, const PassReport& pass) {
            auto copy = std::make_shared<const Film>(film);
            if (convergence) convergence->record(film, pass);
            std::lock_guard lock(mutex_);
            if (convergence) {
                const ConvergencePoint& p = convergence->points().back();
                convergence_.push_back({p.pass.seconds, p.error.rmse, p.ssim});
            }
            image_ = std::move(copy);
            ++image_version_;
            passes_ = pass.passes;
            seconds_ = pass.seconds;
            spp_ = pass.spp;
        };
        {
            std::lock_guard lock(mutex_);
            exposure_ = scene.camera.exposure;
            gamma_ = scene.film.gamma;
            width_ = scene.film.width;
            height_ = scene.film.height;
        }
        const auto accel = make_intersector(scene, scene.accel, resolve_threads(opt.threads));
        RenderResult res = render(scene, rs, *accel, opt);
        // The EXR as the command line writes it, kept for download.
        const double spp = mean_samples(res);
        ImageAttributes attrs =
            job_attributes({req.scene_path, request_text(req)}, scene, rs, opt,
                           res.stats.wall_seconds, res.stats.passes, spp, accel->name());
        attrs.push_back({"foton:threads", std::to_string(res.stats.threads)});
        if (cancel_) attrs.push_back({"foton:interrupted", "true"});
        ExrRenderInfo info = job_exr_info(scene, res.stats.wall_seconds, spp);
        describe_sample_counts(res, attrs, info, rs.aovs);
        auto bytes =
            std::make_shared<const std::string>(encode_exr("foton.exr", res.film, attrs, info));
        // The AOVs for the page (the sample counts as one more float layer).
        std::vector<AovLayer> layers = std::move(res.aovs);
        if ((rs.aovs & kAovSamples) && res.samples_per_pixel.size() == res.film.pixels.size())
            layers.push_back(samples_layer(res.samples_per_pixel));
        auto aovs = std::make_shared<const std::vector<AovLayer>>(std::move(layers));
        auto final_image = std::make_shared<const Film>(std::move(res.film));
        std::lock_guard lock(mutex_);
        aovs_ = std::move(aovs);
        image_ = std::move(final_image);
        ++image_version_;
        exr_ = std::move(bytes);
        passes_ = res.stats.passes;
        seconds_ = res.stats.wall_seconds;
        rays_per_second_ = res.stats.wall_seconds > 0
                               ? double(res.stats.total_rays()) / res.stats.wall_seconds
                               : 0.0;
        stats_table_ = res.stats.table();
        state_ = cancel_ ? "stopped" : "done";
    } catch (const InputError& e) {
        std::lock_guard lock(mutex_);
        state_ = "error";
        message_ = e.what();
    } catch (const std::exception& e) {
        std::lock_guard lock(mutex_);
        state_ = "error";
        message_ = std::string("internal error: ") + e.what();
    }
}

std::string RenderSession::status_json() const {
    std::lock_guard lock(mutex_);
    nlohmann::ordered_json j = {{"state", state_},
                                {"scene", scene_name_},
                                {"message", message_},
                                {"passes", passes_},
                                {"seconds", seconds_},
                                {"spp", spp_},
                                {"rays_per_second", rays_per_second_},
                                {"width", width_},
                                {"height", height_}};
    if (const std::optional<Progress::View> v = progress_.view(); v && state_ == "running")
        j["progress"] = {{"fraction", v->fraction}, {"eta", v->eta}, {"task", v->name}};
    j["stats"] = stats_table_;
    j["exposure"] = exposure_;
    j["gamma"] = gamma_;
    j["aovs"] = nlohmann::ordered_json::array();
    if (aovs_)
        for (const AovLayer& l : *aovs_) j["aovs"].push_back(l.name);
    j["convergence"] = convergence_;
    // Invalid UTF-8 (a file name, a message quoting a file) is replaced, never thrown.
    return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::shared_ptr<const std::string> RenderSession::png(float stops) const {
    std::shared_ptr<const Film> film;
    uint64_t version = 0;
    float exposure = 1.f, gamma = 2.2f;
    {
        std::lock_guard lock(mutex_);
        film = image_;
        version = image_version_;
        exposure = exposure_;
        gamma = gamma_;
    }
    if (!film) return nullptr;
    std::lock_guard lock(png_mutex_);
    if (!png_ || png_version_ != version || png_stops_ != stops) {
        png_ = std::make_shared<const std::string>(
            encode_png(*film, exposure * std::exp2(stops), gamma));
        png_version_ = version;
        png_stops_ = stops;
    }
    return png_;
}

std::shared_ptr<const PixelData> RenderSession::pixels(const std::string& layer) const {
    std::shared_ptr<const Film> film;
    std::shared_ptr<const std::vector<AovLayer>> aovs;
    uint64_t version = 0;
    {
        std::lock_guard lock(mutex_);
        film = image_;
        aovs = aovs_;
        version = image_version_;
    }
    if (!film) return nullptr;
    const bool image = layer.empty() || layer == "image";
    const AovLayer* aov = image || !aovs ? nullptr : find_aov(*aovs, layer);
    if (!image && !aov) return nullptr;
    // One copy per image and layer, shared by concurrent requests (as png()).
    std::lock_guard lock(png_mutex_);
    if (pixels_ && pixels_version_ == version && pixels_layer_ == layer) return pixels_;
    auto out = std::make_shared<PixelData>();
    out->width = film->width;
    out->height = film->height;
    if (image) {
        out->channels = {"R", "G", "B"};
        out->bytes.assign(reinterpret_cast<const char*>(film->pixels.data()),
                          film->pixels.size() * sizeof(RGB));
    } else {
        out->channels = aov->channels;
        out->bytes.assign(reinterpret_cast<const char*>(aov->values.data()),
                          aov->values.size() * sizeof(float));
    }
    pixels_ = out;
    pixels_version_ = version;
    pixels_layer_ = layer;
    return pixels_;
}

std::shared_ptr<const std::string> RenderSession::exr() const {
    std::lock_guard lock(mutex_);
    return exr_;
}

}  // namespace foton::app
