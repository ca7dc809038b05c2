#pragma once
// When a progressive render stops (a pass count, a time budget) and when it fires the
// snapshots of an equal-time study: every pass loop (camera tiles, light tracer, SPPM)
// asks it after each pass.
#include <chrono>
#include <cstdint>
#include <functional>

#include "engine/film/film.h"
#include "render_options.h"

namespace foton {

// Decides when the progressive loop stops and fires the snapshots.
class PassControl {
  public:
    PassControl(const RenderOptions& opt) : opt_(opt), start_(std::chrono::steady_clock::now()) {}
    double elapsed() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }
    // After pass `passes` (1-based) has finished: whether to run another.
    // `spp`: the mean samples per pixel so far (for the snapshot's metadata).
    bool another(uint32_t passes, const std::function<Film()>& image,
                 const std::function<double()>& spp) {
        const double t = elapsed();
        while (next_snapshot_ < opt_.snapshot_times.size() &&
               t >= opt_.snapshot_times[next_snapshot_]) {
            if (opt_.on_snapshot)
                opt_.on_snapshot(image(), opt_.snapshot_times[next_snapshot_], t, passes, spp());
            ++next_snapshot_;
        }
        if (opt_.max_passes > 0 && passes >= opt_.max_passes) return false;
        return opt_.time_limit > 0.f && t < double(opt_.time_limit);
    }

  private:
    const RenderOptions& opt_;
    std::chrono::steady_clock::time_point start_;
    std::size_t next_snapshot_ = 0;
};

}  // namespace foton
