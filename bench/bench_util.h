#pragma once
// Small helpers shared by the whole-renderer benchmark binaries.
#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

namespace foton::bench {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

inline double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// A scene of the repository's scenes/ directory.
inline std::string scene_path(const char* name) {
    return std::string(FOTON_SOURCE_DIR) + "/scenes/" + name;
}

}  // namespace foton::bench
