#include "py_render.h"

#include <atomic>
#include <exception>

#include <pybind11/stl.h>

#include "engine/accel/intersector.h"
#include "engine/core/error.h"
#include "py_convert.h"

namespace foton::py {

namespace {

// A keyword argument's value as the settings' text: booleans as true/false, a list of names
// (aov=["albedo", "depth"]) comma-separated, anything else by str().
std::string setting_text(const pyb::handle& v) {
    if (pyb::isinstance<pyb::bool_>(v)) return v.cast<bool>() ? "true" : "false";
    if (pyb::isinstance<pyb::list>(v) || pyb::isinstance<pyb::tuple>(v)) {
        std::string s;
        for (const pyb::handle& item : v) s += (s.empty() ? "" : ",") + setting_text(item);
        return s;
    }
    return pyb::str(v).cast<std::string>();
}

float time_value(const pyb::handle& v) {
    try {
        return v.cast<float>();
    } catch (const pyb::cast_error&) {
        throw InputError("render(time=)", 0, "must be a number of seconds, not " + setting_text(v));
    }
}

// The request `render(**kwargs)` makes, in the command line's terms: each setting reported
// under `render(key=...)` when its value is bad, as --spp is on the command line.
app::JobRequest job_request(const std::string& path, const pyb::kwargs& kwargs,
                            pyb::object& progress, std::string& text) {
    app::JobRequest r;
    r.scene = path;
    r.names = {"render(spp=)", "render(passes=)", "render(time=)"};
    for (const auto& [k, v] : kwargs) {
        const std::string key = k.cast<std::string>();
        if (key == "progress") {
            progress = pyb::reinterpret_borrow<pyb::object>(v);
            continue;
        }
        if (v.is_none()) continue;
        const std::string value = setting_text(v);
        text += (text.empty() ? "" : ", ") + key + "=" + value;
        const std::string flag = "render(" + key + "=)";
        if (key == "spp")
            r.spp = value;
        else if (key == "passes")
            r.passes = value;
        else if (key == "time")
            r.time = time_value(v);
        else if (key == "width")
            r.image.width = value;
        else if (key == "height")
            r.image.height = value;
        else if (key == "accel")
            r.accel = value;
        else if (key == "integrator")
            r.flags.push_back({"type", value, flag});
        else if (key == "threads")
            r.flags.push_back({"num_threads", value, flag});
        else
            r.flags.push_back({key, value, flag});
    }
    return r;
}

}  // namespace

PyScene::PyScene(const std::string& path, const pyb::dict& settings) : path_(path) {
    RendererOverrides set;
    for (const auto& [k, v] : settings) set.push_back({k.cast<std::string>(), setting_text(v)});
    scene_ = load_scene(path, set);
}

PyResult PyScene::render(const pyb::kwargs& kwargs) const {
    pyb::object progress = pyb::none();
    std::string text;
    const app::JobRequest request = job_request(path_, kwargs, progress, text);
    app::RenderJob job = app::configure_job(scene_, request);
    RenderOptions& opt = job.options;
    // The callback runs between passes with the GIL; an exception it raises (KeyboardInterrupt
    // from Ctrl-C included) stops the render after that pass and is raised again here.
    std::atomic<bool> cancel{false};
    std::exception_ptr raised;
    opt.cancel = &cancel;
    opt.on_pass = [&](const Film& film, const PassReport& pass) {
        pyb::gil_scoped_acquire gil;
        if (raised) return;
        try {
            if (PyErr_CheckSignals() != 0) throw pyb::error_already_set();
            if (!progress.is_none()) {
                pyb::dict report;
                report["passes"] = pass.passes;
                report["seconds"] = pass.seconds;
                report["cpu_seconds"] = pass.cpu_seconds;
                report["spp"] = pass.spp;
                report["last"] = pass.last;
                progress(to_array(film), report);
            }
        } catch (...) {
            raised = std::current_exception();
            cancel = true;
        }
    };
    std::shared_ptr<RenderResult> result;
    const char* accel_name = nullptr;
    {
        pyb::gil_scoped_release nogil;
        const auto accel =
            make_intersector(job.scene, job.scene.accel, resolve_threads(opt.threads));
        accel_name = accel->name();
        result =
            std::make_shared<RenderResult>(foton::render(job.scene, job.settings, *accel, opt));
    }
    if (raised) std::rethrow_exception(raised);
    return PyResult(std::move(result), std::move(job), path_, "render(" + text + ")", accel_name);
}

PyResult::PyResult(std::shared_ptr<const RenderResult> result, app::RenderJob job,
                   const std::string& scene_path, const std::string& request, const char* accel)
    : result_(std::move(result)),
      width_(job.scene.film.width),
      height_(job.scene.film.height),
      spp_(app::mean_samples(*result_)),
      stats_json_(result_->stats.json()) {
    attrs_ = app::job_attributes({scene_path, request}, job.scene, job.settings, job.options,
                                 result_->stats.wall_seconds, result_->stats.passes, spp_, accel);
    attrs_.push_back({"foton:threads", std::to_string(result_->stats.threads)});
    info_ = app::job_exr_info(job.scene, result_->stats.wall_seconds, spp_);
    app::describe_sample_counts(*result_, attrs_, info_, job.settings.aovs);
}

pyb::array_t<float> PyResult::image() const {
    return to_array(result_->film);
}

pyb::dict PyResult::aovs() const {
    pyb::dict d;
    for (const AovLayer& l : result_->aovs) d[l.name.c_str()] = to_array(l, width_, height_);
    return d;
}

pyb::array_t<uint32_t> PyResult::samples() const {
    return to_array(result_->samples_per_pixel, width_, height_);
}

pyb::object PyResult::stats() const {
    return pyb::module_::import("json").attr("loads")(stats_json_);
}

pyb::dict PyResult::attributes() const {
    pyb::dict d;
    for (const auto& [k, v] : attrs_) d[k.c_str()] = v;
    return d;
}

void PyResult::write_exr(const std::string& path) const {
    foton::write_exr(path, result_->film, attrs_, info_);
}

}  // namespace foton::py
