#pragma once
// The Python module's scene and result: a scene is loaded once and rendered with any settings
// through the command line's own job (app/render_job.h: the same parsers, limits and
// messages), and a result holds the image, the AOVs, the sample counts, the statistics and the
// EXR attributes `foton render` writes.
#include <memory>
#include <optional>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "engine/app/render_job.h"

namespace foton::py {

namespace pyb = pybind11;

class PyResult {
  public:
    PyResult(std::shared_ptr<const RenderResult> result, app::RenderJob job,
             const std::string& scene_path, const std::string& request, const char* accel);
    pyb::array_t<float> image() const;
    pyb::dict aovs() const;
    pyb::array_t<uint32_t> samples() const;
    pyb::object stats() const;
    pyb::dict attributes() const;
    double spp() const { return spp_; }
    uint32_t passes() const { return result_->stats.passes; }
    double seconds() const { return result_->stats.wall_seconds; }
    // The EXR `foton render` would write for this render (AOVs and metadata included).
    void write_exr(const std::string& path) const;

  private:
    std::shared_ptr<const RenderResult> result_;
    int width_, height_;
    double spp_;
    std::string stats_json_;
    ImageAttributes attrs_;
    ExrRenderInfo info_;
};

class PyScene {
  public:
    // `settings` (key=value renderer settings) apply at load, as --set does.
    PyScene(const std::string& path, const pyb::dict& settings);
    // Renders with `kwargs`: integrator, spp, passes, time, seed, threads, width, height,
    // accel, aov (a name or a list), progress (a callable(image, report)), and any renderer
    // setting by its key. Bad input raises foton.InputError with the command line's message.
    PyResult render(const pyb::kwargs& kwargs) const;
    const std::string& path() const { return path_; }
    int width() const { return scene_.film.width; }
    int height() const { return scene_.film.height; }

  private:
    std::string path_;
    Scene scene_;
};

}  // namespace foton::py
