#include "render_options.h"

#include <algorithm>

#include <tbb/global_control.h>
#include <tbb/info.h>

namespace foton {

int resolve_threads(int requested) {
    // oneTBB never runs more threads than its global limit (the hardware's by default): a
    // larger request is bounded to what can actually run, and that is what gets recorded.
    const int limit =
        int(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
    return requested > 0 ? std::min({requested, limit, kMaxThreads})
                         : std::min(tbb::info::default_concurrency(), kMaxThreads);
}

}  // namespace foton
