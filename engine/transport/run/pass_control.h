#pragma once
// When a progressive render stops (a pass count, a time budget), and what it reports between
// passes: the snapshots of an equal-time study and the per-pass observer (the live preview,
// convergence tracking). Every pass loop (camera tiles, light tracer, SPPM) asks it after
// each pass.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <ctime>
#include <functional>
#include <string_view>

#include "engine/core/progress.h"
#include "engine/film/film.h"
#include "render_options.h"

namespace foton {

// Decides when the progressive loop stops and calls the snapshot and pass observers.
class PassControl {
  public:
    explicit PassControl(const RenderOptions& opt)
        : opt_(opt), start_(opt.start.value_or(RenderStart::now())) {}
    // Seconds since the render started, without the time the observers took.
    double elapsed() const { return wall() - observer_seconds_; }
    double cpu_elapsed() const { return cpu() - observer_cpu_seconds_; }
    // When the render began (the time budget counts from here).
    std::chrono::steady_clock::time_point start() const { return start_.wall; }
    // The progress of the passes: `per_pass` items each (tiles, light-path chunks), or the
    // time budget's clock.
    ProgressTask task(std::string_view name, uint64_t per_pass) const {
        if (opt_.time_limit > 0.f)
            return ProgressTask(opt_.progress, name, double(opt_.time_limit), start_.wall);
        return ProgressTask(opt_.progress, name, per_pass * std::max<uint32_t>(1, opt_.max_passes));
    }
    // After pass `passes` (1-based) has finished: whether to run another. `image` makes the
    // image so far and `spp` its mean samples per pixel; both are called only when an
    // observer needs them. `stop` ends the render here whatever the options say (an
    // adaptive render's single pass).
    // Across MPI ranks rank 0 decides (its clock, its observers) and tells the others, so
    // all run the same passes, and a cancel on any rank (a signal that reached one process)
    // stops them all after this pass; `image` then runs on every rank (it may gather the
    // image to rank 0) and `spp` on rank 0 after it; the observers run on rank 0 only.
    bool another(uint32_t passes, const std::function<Film()>& image,
                 const std::function<double()>& spp, bool stop = false) {
        const Cluster& cluster = cluster_or_solo(opt_.cluster);
        const double t = elapsed();
        const bool cancelled = opt_.cancel && opt_.cancel->load();
        bool more = !stop && !cancelled;
        if (opt_.max_passes > 0 && passes >= opt_.max_passes)
            more = false;
        else if (opt_.time_limit > 0.f)
            more = more && t < double(opt_.time_limit);
        else
            more = more && opt_.max_passes > 0;
        uint32_t due = 0;  // snapshots whose time has come
        while (next_snapshot_ + due < opt_.snapshot_times.size() &&
               t >= opt_.snapshot_times[next_snapshot_ + due])
            ++due;
        struct Decision {
            uint8_t more, observe, cancelled;
            uint32_t due;
        } d{uint8_t(more), uint8_t((due > 0 && opt_.on_snapshot) || opt_.on_pass),
            uint8_t(cancelled), due};
        if (cluster.distributed()) {
            Bytes b;
            pack_value(b, d);
            const std::vector<Bytes> all = cluster.all_gather(b);
            d = Unpacker(all[0]).value<Decision>();
            for (const Bytes& other : all)
                if (Unpacker(other).value<Decision>().cancelled) d.more = 0;
        }
        const double wall0 = wall(), cpu0 = cpu();
        Film film;
        if (d.observe) film = image();
        if (cluster.root()) {
            for (uint32_t i = 0; i < d.due; ++i)
                if (opt_.on_snapshot)
                    opt_.on_snapshot(film, opt_.snapshot_times[next_snapshot_ + i], t, passes,
                                     spp());
            if (opt_.on_pass)
                opt_.on_pass(film, PassReport{passes, t, cpu_elapsed(), spp(), !d.more});
        }
        next_snapshot_ += d.due;
        if (d.observe) {
            observer_seconds_ += wall() - wall0;
            observer_cpu_seconds_ += cpu() - cpu0;
        }
        return d.more;
    }

    // The progressive loop every family runs: pass(k) for k = 0, 1, ... until another() says
    // stop (`image` and `spp` as there; `stop`: this is the only pass). Returns the passes
    // run, at least one.
    uint32_t run(const std::function<void(uint32_t)>& pass, const std::function<Film()>& image,
                 const std::function<double()>& spp, bool stop = false) {
        uint32_t passes = 0;
        do {
            pass(passes);
            ++passes;
        } while (another(passes, image, spp, stop));
        return passes;
    }

  private:
    double wall() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_.wall)
            .count();
    }
    // The process's CPU time (every thread's) since the render started.
    double cpu() const { return double(std::clock() - start_.cpu) / CLOCKS_PER_SEC; }

    const RenderOptions& opt_;
    RenderStart start_;
    double observer_seconds_ = 0.0, observer_cpu_seconds_ = 0.0;
    std::size_t next_snapshot_ = 0;
};

}  // namespace foton
