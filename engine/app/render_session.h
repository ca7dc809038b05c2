#pragma once
// A render the web page started: its settings, its thread, what it has made so far. Every
// member function is thread-safe (the HTTP handlers call them from their own threads).
#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "engine/core/progress.h"
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
    // The image so far (or the final one), empty before the first pass.
    std::optional<Film> image(float& exposure, float& gamma) const;
    // The last finished render's EXR file contents ("" when there is none).
    std::string exr_bytes() const;

  private:
    void run(SessionRequest request);

    mutable std::mutex mutex_;
    std::thread thread_;
    std::atomic<bool> cancel_{false};
    Progress progress_;
    std::string state_ = "idle", message_, stats_table_, scene_name_;
    std::optional<Film> image_;
    float exposure_ = 1.f, gamma_ = 2.2f;
    uint32_t passes_ = 0;
    double seconds_ = 0.0, spp_ = 0.0, rays_per_second_ = 0.0;
    int width_ = 0, height_ = 0;
    std::string exr_;  // the final image as written
};

}  // namespace foton::app
