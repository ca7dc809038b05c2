#include "stats.h"

#include <nlohmann/json.hpp>

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
    for (int i = 0; i < kNumStages; ++i) stage_wall[i] = stage_wall[i] || o.stage_wall[i];
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
    if (error_confidence > 0.f) {
        std::snprintf(buf, sizeof buf,
                      "error bound (%.3g %% confidence): mean %.4g per pixel, %.4g of the mean "
                      "luminance %.4g\n",
                      100.0 * double(error_confidence), error_bound,
                      error_mean_value > 0 ? error_bound / error_mean_value : 0.0,
                      error_mean_value);
        s += buf;
    }
    if (adaptive_uniform > 0) {
        std::snprintf(buf, sizeof buf,
                      "adaptive photons: %.4g %% of %llu uniform paths seen, %.3g %% of %llu "
                      "mutations accepted\n",
                      100.0 * double(adaptive_seen) / double(adaptive_uniform),
                      (unsigned long long)adaptive_uniform,
                      adaptive_mutations
                          ? 100.0 * double(adaptive_accepted) / double(adaptive_mutations)
                          : 0.0,
                      (unsigned long long)adaptive_mutations);
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
                  "tests: ray/triangle %llu, ray/sphere %llu, ray/curve %llu, ray/shape %llu, "
                  "grid cells %llu, bvh nodes %llu, instance visits %llu\n",
                  (unsigned long long)trace.triangle_tests, (unsigned long long)trace.sphere_tests,
                  (unsigned long long)trace.curve_tests, (unsigned long long)trace.shape_tests,
                  (unsigned long long)trace.cells, (unsigned long long)trace.bvh_nodes,
                  (unsigned long long)trace.instance_visits);
    s += buf;
    // Seconds are thread time (summed over the threads that ran the stage) unless the row
    // says wall (one clock around parallel work).
    s += "stage             seconds  time        items      items/s\n";
    for (int i = 0; i < kNumStages; ++i) {
        if (stage_items[i] == 0 && stage_seconds[i] == 0.0) continue;
        std::snprintf(buf, sizeof buf, "%-16s %8.3f  %-6s %10llu %12.4g\n", stage_name(Stage(i)),
                      stage_seconds[i], stage_wall[i] ? "wall" : "thread",
                      (unsigned long long)stage_items[i],
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

nlohmann::ordered_json RenderStats::json_object(const nlohmann::ordered_json& run) const {
    using J = nlohmann::ordered_json;
    J j;
    j["schema_version"] = 2;
    for (const auto& [key, value] : run.items()) j[key] = value;
    j["threads"] = threads;
    j["build_seconds"] = build_seconds;
    j["wall_seconds"] = wall_seconds;
    j["camera_rays"] = camera_rays;
    j["secondary_rays"] = secondary_rays;
    j["shadow_rays"] = shadow_rays;
    j["rays_per_second"] = wall_seconds > 0 ? double(total_rays()) / wall_seconds : 0.0;
    j["samples"] = samples;
    j["passes"] = passes;
    j["samples_per_second"] = wall_seconds > 0 ? double(samples) / wall_seconds : 0.0;
    j["triangle_tests"] = trace.triangle_tests;
    j["sphere_tests"] = trace.sphere_tests;
    j["curve_tests"] = trace.curve_tests;
    j["shape_tests"] = trace.shape_tests;
    j["grid_cells"] = trace.cells;
    j["bvh_nodes"] = trace.bvh_nodes;
    j["instance_visits"] = trace.instance_visits;
    j["cache_records"] = cache_records;
    j["cache_stored"] = cache_stored;
    j["cache_lookups"] = cache.lookups;
    j["cache_interpolated"] = cache.interpolated;
    j["cache_visibility_rejections"] = cache.visibility_rejections;
    j["cache_fill_seconds"] = cache_fill_seconds;
    j["photon_seconds"] = photon_seconds;
    if (error_confidence > 0.f) {
        j["error_bound"] = error_bound;
        j["error_mean_luminance"] = error_mean_value;
        j["error_confidence"] = error_confidence;
    }
    j["photons_global"] = photons_global;
    j["photons_caustic"] = photons_caustic;
    j["shadow_rays_saved"] = shadow_rays_saved;
    j["adaptive_uniform"] = adaptive_uniform;
    j["adaptive_seen"] = adaptive_seen;
    j["adaptive_mutations"] = adaptive_mutations;
    j["adaptive_accepted"] = adaptive_accepted;
    j["cache_candidates"] = cache.candidates;
    j["cache_used"] = cache.used;
    j["cache_visibility_tests"] = cache.visibility_tests;
    J stages = J::object();
    for (int i = 0; i < kNumStages; ++i)
        stages[stage_name(Stage(i))] = {{"thread_seconds", stage_seconds[i]},
                                        {"items", stage_items[i]},
                                        {"time", stage_wall[i] ? "wall" : "thread"}};
    j["stages"] = std::move(stages);
    J nodes = J::array(), edges = J::array();
    for (const GraphStats::Node& n : graph.nodes)
        nodes.push_back({{"name", n.name},
                         {"busy_seconds", n.busy_seconds},
                         {"items", n.items},
                         {"runs", n.runs},
                         {"time", n.thread_time ? "thread" : "wall"}});
    for (const auto& [from, to] : graph.edges)
        edges.push_back({graph.nodes[from].name, graph.nodes[to].name});
    j["graph"] = {{"nodes", std::move(nodes)}, {"edges", std::move(edges)}};
    return j;
}

std::string RenderStats::json(const nlohmann::ordered_json& run) const {
    // Invalid UTF-8 (a file name) is replaced, never thrown.
    return json_object(run).dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

std::string RenderStats::json() const {
    return json(nlohmann::ordered_json::object());
}

}  // namespace foton
