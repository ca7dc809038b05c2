#pragma once
// What a render is doing now, for a progress line or a web page: the tasks in flight (a
// photon pass, the camera tiles, a time budget), how far each has got and when it should end.
// The renderer reports (begin, advance, end; thread-safe, an atomic add per advance) and
// knows nothing of terminals; a viewer polls view() and may ask to be told when a task
// begins or ends.
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

namespace foton {

class Progress {
  public:
    using Clock = std::chrono::steady_clock;

    // The task a viewer shows: the one expected to end last, else the latest begun.
    struct View {
        std::string name;
        double fraction = -1.0;  // 0..1, or < 0 when the task's size is unknown
        double elapsed = 0.0;    // seconds since the task began
        double eta = -1.0;       // seconds to its end, or < 0 when unknown
        int others = 0;          // further tasks in flight
    };

    // Starts a task of `total` items (0: unknown). Returns its slot, or -1 when every slot
    // is taken (the task then goes unreported).
    int begin(std::string_view name, uint64_t total);
    // Starts a task that ends when `seconds` have passed since `since` (a time budget).
    int begin_budget(std::string_view name, double seconds, Clock::time_point since);
    void advance(int slot, uint64_t items) {
        if (slot >= 0) slots_[std::size_t(slot)].done.fetch_add(items, std::memory_order_relaxed);
    }
    void end(int slot);
    std::optional<View> view() const;
    // Called (from the reporting thread) whenever a task begins or ends.
    void on_change(std::function<void()> f);

  private:
    static constexpr std::size_t kSlots = 16;
    struct Slot {
        bool active = false;
        std::string name;
        uint64_t total = 0;
        double budget = 0.0;  // > 0: a time budget
        Clock::time_point start;
        uint64_t sequence = 0;  // when it began, for "latest"
        std::atomic<uint64_t> done{0};
    };
    void changed();
    mutable std::mutex mutex_;
    std::array<Slot, kSlots> slots_;
    uint64_t sequence_ = 0;
    std::function<void()> on_change_;
};

// A task for the length of a scope. With no Progress it does nothing.
class ProgressTask {
  public:
    ProgressTask(Progress* p, std::string_view name, uint64_t total)
        : p_(p), slot_(p ? p->begin(name, total) : -1) {}
    ProgressTask(Progress* p, std::string_view name, double seconds,
                 Progress::Clock::time_point since)
        : p_(p), slot_(p ? p->begin_budget(name, seconds, since) : -1) {}
    ~ProgressTask() {
        if (p_) p_->end(slot_);
    }
    ProgressTask(const ProgressTask&) = delete;
    ProgressTask& operator=(const ProgressTask&) = delete;
    void advance(uint64_t items = 1) const {
        if (p_) p_->advance(slot_, items);
    }

  private:
    Progress* p_;
    int slot_;
};

}  // namespace foton
