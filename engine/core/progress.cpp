#include "progress.h"

#include <algorithm>

namespace foton {

int Progress::begin(std::string_view name, uint64_t total) {
    int slot = -1;
    {
        std::lock_guard lock(mutex_);
        for (std::size_t i = 0; i < kSlots; ++i)
            if (!slots_[i].active) {
                Slot& s = slots_[i];
                s.active = true;
                s.name = name;
                s.total = total;
                s.budget = 0.0;
                s.start = Clock::now();
                s.sequence = ++sequence_;
                s.done.store(0, std::memory_order_relaxed);
                slot = int(i);
                break;
            }
    }
    changed();
    return slot;
}

int Progress::begin_budget(std::string_view name, double seconds, Clock::time_point since) {
    const int slot = begin(name, 0);
    if (slot >= 0) {
        std::lock_guard lock(mutex_);
        slots_[std::size_t(slot)].budget = std::max(seconds, 1e-9);
        slots_[std::size_t(slot)].start = since;
    }
    return slot;
}

void Progress::end(int slot) {
    if (slot < 0) return;
    {
        std::lock_guard lock(mutex_);
        slots_[std::size_t(slot)].active = false;
    }
    changed();
}

std::optional<Progress::View> Progress::view() const {
    std::lock_guard lock(mutex_);
    const Clock::time_point now = Clock::now();
    std::optional<View> best;
    uint64_t best_sequence = 0;
    int active = 0;
    for (const Slot& s : slots_) {
        if (!s.active) continue;
        ++active;
        View v;
        v.name = s.name;
        v.elapsed = std::chrono::duration<double>(now - s.start).count();
        if (s.budget > 0.0) {
            v.fraction = std::min(1.0, v.elapsed / s.budget);
            v.eta = std::max(0.0, s.budget - v.elapsed);
        } else if (s.total > 0) {
            v.fraction =
                std::min(1.0, double(s.done.load(std::memory_order_relaxed)) / double(s.total));
            v.eta = v.fraction > 0.0 ? v.elapsed * (1.0 - v.fraction) / v.fraction : -1.0;
        }
        // Known sizes beat unknown ones; among them the longest to go, else the latest.
        const bool known = v.fraction >= 0.0, best_known = best && best->fraction >= 0.0;
        bool better = !best || (known && !best_known);
        if (best && known == best_known)
            better = known ? v.eta > best->eta : s.sequence > best_sequence;
        if (better) {
            best = v;
            best_sequence = s.sequence;
        }
    }
    if (best) best->others = active - 1;
    return best;
}

void Progress::on_change(std::function<void()> f) {
    std::lock_guard lock(mutex_);
    on_change_ = std::move(f);
}

void Progress::changed() {
    std::function<void()> f;
    {
        std::lock_guard lock(mutex_);
        f = on_change_;
    }
    if (f) f();
}

}  // namespace foton
