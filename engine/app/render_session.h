#pragma once
// A render the web page started: its settings, its thread, what it has made so far. Every
// member function is thread-safe (the HTTP handlers call them from their own threads).
#include <array>
#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "engine/core/progress.h"
#include "engine/film/aov.h"
#include "engine/film/film.h"

namespace foton::app {

struct SessionRequest {
    std::string scene_path;  // resolved by the server from the scene's name
    std::string integrator, accel;
    int threads = 0, width = 0, height = 0;  // 0: the scene's
    uint32_t spp = 1, passes = 0;            // passes 0: fixed spp, one pass
    float time = 0.f;
    uint64_t seed = 0;
    std::map<std::string, std::string> set;  // further <renderer> settings
    // A reference EXR (resolved by the server from its name): the error after every pass.
    std::string reference_path;
    std::optional<float> exclude_above;  // reference pixels brighter than this do not count
};

// One layer's pixels for the page: float32 values, `channels.size()` per pixel, row-major.
struct PixelData {
    int width = 0, height = 0;
    std::vector<std::string> channels;
    std::string bytes;
};

class RenderSession {
  public:
    ~RenderSession();
    // Starts a render; false (and `error` set) when one is running.
    bool start(const SessionRequest& request, std::string& error);
    // Asks the render to stop after the pass in flight.
    void stop();
    // {"state": idle|running|done|stopped|error, ...} for the page.
    std::string status_json() const;
    // The image so far (or the final one) as a PNG, `stops` of exposure added; null before the
    // first pass. Encoded once per image and exposure and shared: concurrent requests for a
    // large image neither copy the film nor encode it again (50 of them once exhausted memory).
    std::shared_ptr<const std::string> png(float stops) const;
    // The last finished render's EXR file contents (null when there is none).
    std::shared_ptr<const std::string> exr() const;
    // The image so far ("" or "image") or an AOV of the finished render (film/aov.h's names)
    // as floats; null when there is no such layer (yet).
    std::shared_ptr<const PixelData> pixels(const std::string& layer) const;

  private:
    void run(SessionRequest request);

    mutable std::mutex mutex_;
    std::thread thread_;
    std::atomic<bool> cancel_{false};
    Progress progress_;
    std::string state_ = "idle", message_, stats_table_, scene_name_;
    std::shared_ptr<const Film> image_;  // replaced, never changed: readers keep their copy
    uint64_t image_version_ = 0;
    float exposure_ = 1.f, gamma_ = 2.2f;
    uint32_t passes_ = 0;
    double seconds_ = 0.0, spp_ = 0.0, rays_per_second_ = 0.0;
    int width_ = 0, height_ = 0;
    std::shared_ptr<const std::string> exr_;             // the final image as written
    std::shared_ptr<const std::vector<AovLayer>> aovs_;  // the finished render's AOVs
    // Error against the reference after each pass: seconds, rmse, ssim.
    std::vector<std::array<double, 3>> convergence_;
    // The last PNG made, for its image version and stops; one encode at a time.
    mutable std::mutex png_mutex_;
    mutable std::shared_ptr<const std::string> png_;
    mutable uint64_t png_version_ = 0;
    mutable float png_stops_ = 0.f;
    mutable std::shared_ptr<const PixelData> pixels_;  // the last layer sent, likewise
    mutable uint64_t pixels_version_ = 0;
    mutable std::string pixels_layer_;
};

}  // namespace foton::app
