#include "stats.h"

#include <cstdio>

namespace foton {

const char* stage_name(Stage s) {
    switch (s) {
        case Stage::Generate:
            return "generate";
        case Stage::Intersect:
            return "intersect";
        case Stage::Shade:
            return "shade";
        case Stage::Occlusion:
            return "occlusion";
        case Stage::Accumulate:
            return "accumulate";
        case Stage::PhotonEmit:
            return "emit";
        case Stage::PhotonIntersect:
            return "photon-intersect";
        case Stage::PhotonTrace:
            return "scatter+store";
        case Stage::PhotonStore:
            return "merge";
        case Stage::Balance:
            return "balance";
        case Stage::Precompute:
            return "irradiance";
        case Stage::GuideBins:
            return "guide-bins";
        case Stage::LightVertices:
            return "light-vertices";
        case Stage::FinalGather:
            return "final-gather";
        case Stage::PhotonEstimate:
            return "photon-estimate";
        case Stage::CacheRecords:
            return "cache-record";
        case Stage::CacheLookup:
            return "cache-lookup";
        case Stage::kCount:
            break;
    }
    return "?";
}

void RenderStats::merge(const RenderStats& o) {
    for_each_summed(*this, o, [](auto& a, const auto& b) { a += b; });
}

std::string RenderStats::table() const {
    char buf[256];
    std::string s;
    std::snprintf(buf, sizeof buf, "threads %d, build %.3f s, render %.3f s wall\n", threads,
                  build_seconds, wall_seconds);
    s += buf;
    std::snprintf(buf, sizeof buf,
                  "rays: camera %llu, secondary %llu, shadow %llu, total %llu (%.3g rays/s wall)\n",
                  (unsigned long long)camera_rays, (unsigned long long)secondary_rays,
                  (unsigned long long)shadow_rays, (unsigned long long)total_rays(),
                  wall_seconds > 0 ? double(total_rays()) / wall_seconds : 0.0);
    s += buf;
    std::snprintf(buf, sizeof buf, "samples %llu in %u passes (%.4g samples/s wall)\n",
                  (unsigned long long)samples, passes,
                  wall_seconds > 0 ? double(samples) / wall_seconds : 0.0);
    s += buf;
    if (photons_global + photons_caustic > 0) {
        std::snprintf(buf, sizeof buf,
                      "photons: global %llu, caustic %llu stored; photon passes + balance %.3f s "
                      "wall\n",
                      (unsigned long long)photons_global, (unsigned long long)photons_caustic,
                      photon_seconds);
        s += buf;
    }
    if (shadow_rays_saved > 0) {
        std::snprintf(buf, sizeof buf, "shadow photons decided %llu shadow rays\n",
                      (unsigned long long)shadow_rays_saved);
        s += buf;
    }
    if (cache_records > 0 || cache.lookups > 0) {
        std::snprintf(
            buf, sizeof buf,
            "irradiance cache: %llu records stored, %llu computed, fill %.3f s wall; %llu "
            "lookups, %.1f%% interpolated, %.2f records each; visibility rejected %llu of %llu\n",
            (unsigned long long)cache_stored, (unsigned long long)cache_records, cache_fill_seconds,
            (unsigned long long)cache.lookups,
            cache.lookups ? 100.0 * double(cache.interpolated) / double(cache.lookups) : 0.0,
            cache.interpolated ? double(cache.used) / double(cache.interpolated) : 0.0,
            (unsigned long long)cache.visibility_rejections,
            (unsigned long long)cache.visibility_tests);
        s += buf;
    }
    std::snprintf(buf, sizeof buf,
                  "tests: ray/triangle %llu, ray/sphere %llu, grid cells %llu, bvh nodes %llu, "
                  "instance visits %llu\n",
                  (unsigned long long)trace.triangle_tests, (unsigned long long)trace.sphere_tests,
                  (unsigned long long)trace.cells, (unsigned long long)trace.bvh_nodes,
                  (unsigned long long)trace.instance_visits);
    s += buf;
    s += "stage        thread-s      items     items/thread-s\n";
    for (int i = 0; i < kNumStages; ++i) {
        if (stage_items[i] == 0 && stage_seconds[i] == 0.0) continue;
        std::snprintf(buf, sizeof buf, "%-12s %8.3f %10llu %18.4g\n", stage_name(Stage(i)),
                      stage_seconds[i], (unsigned long long)stage_items[i],
                      stage_seconds[i] > 0 ? double(stage_items[i]) / stage_seconds[i] : 0.0);
        s += buf;
    }
    if (!graph.nodes.empty()) {
        s += "graph node                busy-s      items   runs  after\n";
        for (std::size_t i = 0; i < graph.nodes.size(); ++i) {
            const GraphStats::Node& n = graph.nodes[i];
            std::string after;
            for (const auto& [from, to] : graph.edges)
                if (to == i) after += (after.empty() ? "" : ", ") + graph.nodes[from].name;
            std::snprintf(buf, sizeof buf, "%-24s %9.3f %10llu %6llu  %s\n", n.name.c_str(),
                          n.busy_seconds, (unsigned long long)n.items, (unsigned long long)n.runs,
                          after.c_str());
            s += buf;
        }
    }
    return s;
}

std::string RenderStats::json(const std::vector<std::pair<std::string, std::string>>& run) const {
    char buf[4096];
    std::string s = "{\n  \"schema_version\": 2,\n";
    for (const auto& [key, value] : run) s += "  \"" + key + "\": " + value + ",\n";
    std::snprintf(
        buf, sizeof buf,
        "  \"threads\": %d,\n  \"build_seconds\": %.6f,\n  \"wall_seconds\": %.6f,\n"
        "  \"camera_rays\": %llu,\n  \"secondary_rays\": %llu,\n  \"shadow_rays\": %llu,\n"
        "  \"rays_per_second\": %.6g,\n  \"samples\": %llu,\n  \"passes\": %u,\n"
        "  \"samples_per_second\": %.6g,\n  \"triangle_tests\": %llu,\n"
        "  \"sphere_tests\": %llu,\n  \"grid_cells\": %llu,\n  \"bvh_nodes\": %llu,\n"
        "  \"instance_visits\": %llu,\n"
        "  \"cache_records\": %llu,\n  \"cache_stored\": %llu,\n  \"cache_lookups\": %llu,\n"
        "  \"cache_interpolated\": %llu,\n  \"cache_visibility_rejections\": %llu,\n"
        "  \"cache_fill_seconds\": %.6f,\n  \"photon_seconds\": %.6f,\n"
        "  \"photons_global\": %llu,\n  \"photons_caustic\": %llu,\n"
        "  \"shadow_rays_saved\": %llu,\n  \"cache_candidates\": %llu,\n"
        "  \"cache_used\": %llu,\n  \"cache_visibility_tests\": %llu,\n"
        "  \"stages\": {\n",
        threads, build_seconds, wall_seconds, (unsigned long long)camera_rays,
        (unsigned long long)secondary_rays, (unsigned long long)shadow_rays,
        wall_seconds > 0 ? double(total_rays()) / wall_seconds : 0.0, (unsigned long long)samples,
        passes, wall_seconds > 0 ? double(samples) / wall_seconds : 0.0,
        (unsigned long long)trace.triangle_tests, (unsigned long long)trace.sphere_tests,
        (unsigned long long)trace.cells, (unsigned long long)trace.bvh_nodes,
        (unsigned long long)trace.instance_visits, (unsigned long long)cache_records,
        (unsigned long long)cache_stored, (unsigned long long)cache.lookups,
        (unsigned long long)cache.interpolated, (unsigned long long)cache.visibility_rejections,
        cache_fill_seconds, photon_seconds, (unsigned long long)photons_global,
        (unsigned long long)photons_caustic, (unsigned long long)shadow_rays_saved,
        (unsigned long long)cache.candidates, (unsigned long long)cache.used,
        (unsigned long long)cache.visibility_tests);
    s += buf;
    for (int i = 0; i < kNumStages; ++i) {
        std::snprintf(buf, sizeof buf,
                      "    \"%s\": {\"thread_seconds\": %.6f, \"items\": %llu}%s\n",
                      stage_name(Stage(i)), stage_seconds[i], (unsigned long long)stage_items[i],
                      i + 1 < kNumStages ? "," : "");
        s += buf;
    }
    s += "  },\n  \"graph\": {\n    \"nodes\": [";
    for (std::size_t i = 0; i < graph.nodes.size(); ++i) {
        const GraphStats::Node& n = graph.nodes[i];
        std::snprintf(buf, sizeof buf,
                      "%s\n      {\"name\": \"%s\", \"busy_seconds\": %.6f, \"items\": %llu, "
                      "\"runs\": %llu, \"time\": \"%s\"}",
                      i ? "," : "", n.name.c_str(), n.busy_seconds, (unsigned long long)n.items,
                      (unsigned long long)n.runs, n.thread_time ? "thread" : "wall");
        s += buf;
    }
    s += "\n    ],\n    \"edges\": [";
    for (std::size_t i = 0; i < graph.edges.size(); ++i) {
        std::snprintf(buf, sizeof buf, "%s[\"%s\", \"%s\"]", i ? ", " : "",
                      graph.nodes[graph.edges[i].first].name.c_str(),
                      graph.nodes[graph.edges[i].second].name.c_str());
        s += buf;
    }
    s += "]\n  }\n}\n";
    return s;
}

}  // namespace foton
