#include "convergence_log.h"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "engine/film/image_io.h"
#include "engine/film/ssim.h"

namespace foton::app {

namespace {
Film reference_for(const std::string& path, const FilmSettings& film) {
    Film ref = read_exr(path);
    if (!film.cropped() || (ref.width == film.width && ref.height == film.height))
        return fit_reference(std::move(ref), film.width, film.height, path);
    // A reference of the whole image: the window's pixels.
    ref = fit_reference(std::move(ref), film.full_width, film.full_height, path);
    Film window(film.width, film.height);
    for (int y = 0; y < film.height; ++y)
        for (int x = 0; x < film.width; ++x) window.at(x, y) = ref.at(film.x0 + x, film.y0 + y);
    return window;
}
}  // namespace

ConvergenceLog::ConvergenceLog(const std::string& path, const FilmSettings& film,
                               std::optional<float> exclude_above)
    : reference_(reference_for(path, film)), mask_(reference_.pixels.size(), 1) {
    if (exclude_above) mask_ = luminance_mask(reference_, *exclude_above);
}

void ConvergenceLog::record(const Film& image, const PassReport& pass) {
    ConvergencePoint p;
    p.pass = pass;
    p.error = compare_images(image, reference_, &mask_);
    p.bias = p.error.mean_a - p.error.mean_b;
    p.ssim = ssim(image, reference_, &mask_);
    points_.push_back(p);
}

namespace {
// Nine significant digits: a float's value survives the round trip.
std::string row(const ConvergencePoint& p, const char* format) {
    char buf[512];
    std::snprintf(buf, sizeof buf, format, p.pass.passes, p.pass.seconds, p.pass.cpu_seconds,
                  p.pass.spp, p.error.rmse, p.error.relative_mse, p.error.mae, double(p.bias.r),
                  double(p.bias.g), double(p.bias.b), p.ssim);
    return buf;
}
}  // namespace

std::string ConvergenceLog::csv() const {
    std::string out =
        "passes,seconds,cpu_seconds,spp,rmse,relative_mse,mae,bias_r,bias_g,bias_b,ssim\n";
    for (const ConvergencePoint& p : points_)
        out += row(p, "%u,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n");
    return out;
}

nlohmann::ordered_json ConvergenceLog::json() const {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (const ConvergencePoint& p : points_)
        out.push_back({{"passes", p.pass.passes},
                       {"seconds", p.pass.seconds},
                       {"cpu_seconds", p.pass.cpu_seconds},
                       {"spp", p.pass.spp},
                       {"rmse", p.error.rmse},
                       {"relative_mse", p.error.relative_mse},
                       {"mae", p.error.mae},
                       {"bias", {p.bias.r, p.bias.g, p.bias.b}},
                       {"ssim", p.ssim}});
    return out;
}

}  // namespace foton::app
