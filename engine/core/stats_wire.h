#pragma once
// A rank's statistics for rank 0 (issue 16: per-rank and merged statistics of an MPI render).
#include "engine/core/cluster.h"
#include "engine/core/stats.h"

namespace foton {

// The counters merge() sums, as bytes.
inline void pack_counters(Bytes& out, const RenderStats& s) {
    RenderStats::for_each_summed(s, s, [&](const auto& v, const auto&) { pack_value(out, v); });
}
// Reads what pack_counters wrote into a RenderStats of those counters alone.
inline RenderStats unpack_counters(Unpacker& in) {
    RenderStats s;
    RenderStats::for_each_summed(
        s, s, [&](auto& v, const auto&) { v = in.value<std::remove_reference_t<decltype(v)>>(); });
    return s;
}

}  // namespace foton
