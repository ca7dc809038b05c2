#pragma once
// Convergence tracking (--reference): after every pass, the error of the image so far
// against a reference, with the pass's wall time, CPU time and samples; written as CSV and
// into the stats JSON, so error-vs-time curves of several methods can be drawn
// (bench/plot_convergence).
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "engine/film/metrics.h"
#include "engine/scene/scene.h"
#include "engine/transport/run/render_options.h"

namespace foton::app {

struct ConvergencePoint {
    PassReport pass;
    ImageError error;
    RGB bias;           // mean of the image minus mean of the reference, per channel
    double ssim = 0.0;  // structural similarity to the reference (film/ssim.h)
};

class ConvergenceLog {
  public:
    // `reference` is read from `path`, fitted to the film (see fit_reference; a reference of
    // the full image is cut to a crop window); pixels whose reference luminance is above
    // `exclude_above` do not count.
    ConvergenceLog(const std::string& path, const FilmSettings& film,
                   std::optional<float> exclude_above);
    void record(const Film& image, const PassReport& pass);
    const std::vector<ConvergencePoint>& points() const { return points_; }
    // One row per pass: passes,seconds,cpu_seconds,spp,rmse,relative_mse,mae,bias_r,...
    std::string csv() const;
    // The same rows as a JSON array of objects.
    nlohmann::ordered_json json() const;

  private:
    Film reference_;
    std::vector<uint8_t> mask_;
    std::vector<ConvergencePoint> points_;
};

}  // namespace foton::app
