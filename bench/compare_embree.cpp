// foton_compare_embree: our traversal forms against Embree's on the same rays, in interleaved
// rounds. This is the one source of the kernel tables in docs/kernels.md.
//
// For each scene it builds our wide BVH and Embree's BVH at medium and high quality, then runs
// `--rounds` rounds. Each round times every form once, ours and Embree's in turn (A B C ... A B
// C ...), so slow drift of a shared machine hits every form alike. The unit of one measurement
// is a pass over the whole ray set in chunks of 4,096 rays (the size Embree's streams get),
// repeated until `--min-time` has passed, after one untimed pass.
// Printed: medians with min-max per cell, and the ratios taken within each round (ours / E1;
// best own form / best Embree form), summarised by their median and range. Also the build
// (1 thread and all threads, in rounds too), bytes per triangle of every structure, and the
// machine: CPU, ISA, cores, load average before and after, date, versions.
//
//   foton_compare_embree [--scenes bunny,dragon,stadium] [--sets primary,diffuse,shadow]
//                        [--rounds 5] [--min-time 0.25] [--threads 1] [--json FILE]
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench/ray_sets.h"
#include "bench/trace_forms.h"
#include "engine/app/build_info.h"
#include "engine/core/cpu_topology.h"
#include "kernels/simd.h"

using namespace foton;
using Clock = std::chrono::steady_clock;

namespace {

constexpr std::size_t kChunk = 4096;

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string item; std::getline(ss, item, ',');)
        if (!item.empty()) out.push_back(item);
    return out;
}

std::string load_average() {
    std::ifstream f("/proc/loadavg");
    std::string a, b, c;
    f >> a >> b >> c;
    return a + " " + b + " " + c;
}

std::string utc_now() {
    const std::time_t t = std::time(nullptr);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M UTC", std::gmtime(&t));
    return buf;
}

std::string isa() {
#if defined(__AVX512BW__)
    return "AVX-512 (W = " + std::to_string(simd::kWidth) + ", BVH nodes of " +
           std::to_string(simd::kHalfWidth) + ")";
#elif defined(__AVX2__)
    return "AVX2 (W = " + std::to_string(simd::kWidth) + ")";
#else
    return "SSE (W = " + std::to_string(simd::kWidth) + ")";
#endif
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string cell(const std::vector<double>& v, int prec) {
    if (v.empty()) return "–";
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    char buf[96];
    std::snprintf(buf, sizeof buf, "%.*f (%.*f-%.*f)", prec, median(v), prec, *lo, prec, *hi);
    return buf;
}

// Seconds per pass of `f` over n rays, chunk by chunk, on the arena's threads.
double time_pass(const bench::TraceForm& f, std::size_t n, tbb::task_arena& arena, int threads,
                 double min_time, std::size_t& hits) {
    auto pass = [&] {
        std::atomic<std::size_t> h{0};
        const std::size_t chunks = (n + kChunk - 1) / kChunk;
        if (threads == 1) {
            for (std::size_t c = 0; c < chunks; ++c)
                h += f.run(c * kChunk, std::min(n, (c + 1) * kChunk));
        } else {
            arena.execute([&] {
                tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
                    h.fetch_add(f.run(c * kChunk, std::min(n, (c + 1) * kChunk)));
                });
            });
        }
        return h.load();
    };
    hits = pass();  // untimed: brings the form's data in
    std::size_t passes = 0;
    const auto t0 = Clock::now();
    double elapsed = 0.0;
    do {
        pass();
        ++passes;
        elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
    } while (elapsed < min_time);
    return elapsed / double(passes);
}

kern::BvhBuildParams::ParallelInvoke tbb_invoke() {
    return [](const std::function<void()>& a, const std::function<void()>& b) {
        tbb::parallel_invoke(a, b);
    };
}

struct Options {
    std::vector<std::string> scenes{"bunny", "dragon", "stadium"};
    std::vector<std::string> sets{"primary", "diffuse", "shadow"};
    int rounds = 5;
    double min_time = 0.25;
    int threads = 1;
    std::string json;
};

}  // namespace

int main(int argc, char** argv) {
    Options o;
    std::string scenes = "bunny,dragon,stadium", sets = "primary,diffuse,shadow";
    CLI::App app{"Our traversal forms against Embree's, on the same rays, in interleaved rounds"};
    app.add_option("--scenes", scenes, "bunny, dragon, teapot, cornell, stadium (comma list)");
    app.add_option("--sets", sets, "primary, diffuse, shadow (comma list)");
    app.add_option("--rounds", o.rounds, "interleaved rounds (at least 5 for the docs' tables)")
        ->check(CLI::Range(1, 1000));
    app.add_option("--min-time", o.min_time, "seconds each form runs per round")
        ->check(CLI::Range(0.0, 60.0));
    app.add_option("--threads", o.threads, "threads (0: all)")->check(CLI::Range(0, 4096));
    app.add_option("--json", o.json, "also write every round's numbers to this JSON file");
    CLI11_PARSE(app, argc, argv);
    o.scenes = split(scenes);
    o.sets = split(sets);
    const int all = int(std::thread::hardware_concurrency());
    const int threads = o.threads == 0 ? all : o.threads;
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, std::max(threads, all));
    tbb::task_arena arena(threads);

    const CpuTopology topo = cpu_topology();
    const std::string load_before = load_average();
    nlohmann::json doc;
    doc["machine"] = {{"cpu", topo.model},
                      {"isa", isa()},
                      {"cores", topo.cores},
                      {"logical_cpus", topo.logical},
                      {"date", utc_now()},
                      {"load_before", load_before},
                      {"embree", RTC_VERSION_STRING},
                      {"compiler", __VERSION__},
                      {"foton_commit", app::git_commit()}};
    doc["settings"] = {
        {"rounds", o.rounds}, {"min_time", o.min_time}, {"threads", threads}, {"chunk", kChunk}};

    std::printf("# Traversal: ours against Embree, %d thread%s, %d interleaved rounds\n\n", threads,
                threads == 1 ? "" : "s", o.rounds);
    std::printf(
        "Machine: %s, %d cores (%d logical), %s; Embree %s, %s; foton %s; %s; load "
        "average before: %s\n\n",
        topo.model.c_str(), topo.cores, topo.logical, isa().c_str(), RTC_VERSION_STRING,
        __VERSION__, app::git_commit(), utc_now().c_str(), load_before.c_str());

    bench::EmbreeDevice device(threads);            // traces on the benchmark's threads
    bench::EmbreeDevice device1(1), device_all(0);  // builds on 1 and on all threads
    for (const std::string& name : o.scenes) {
        const bench::KernelScene scene = bench::load_kernel_scene(name);
        const bench::RaySets rs = bench::make_ray_sets(scene, 1024, 1u << 18);
        const TriangleMesh& m = scene.mesh;
        const double tris = double(m.num_triangles());

        // Build: ours and Embree's, on 1 thread and on all, interleaved; bytes per triangle.
        std::map<std::string, std::vector<double>> build_ms;
        std::map<std::string, double> bytes_per_tri;
        double sah = 0.0;
        kern::TriangleBvh bvh;
        for (int r = 0; r < o.rounds; ++r) {
            for (int t : {1, all}) {
                const std::string th = t == 1 ? "1 thread" : std::to_string(t) + " threads";
                auto p = kern::TriangleBvh::default_params();
                if (t > 1) p.parallel = tbb_invoke();
                kern::TriangleBvh b;
                auto t0 = Clock::now();
                tbb::task_arena build_arena(t);
                build_arena.execute(
                    [&] { b.build(m.positions.data(), m.indices.data(), m.num_triangles(), p); });
                build_ms["bvh, " + th].push_back(
                    std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
                bytes_per_tri["bvh"] = double(b.memory_bytes()) / tris;
                if (t == 1) {
                    // A refit to the same positions: what a moving mesh pays per frame.
                    const kern::TriangleSource src{m.positions.data(), m.indices.data(),
                                                   m.num_triangles()};
                    t0 = Clock::now();
                    b.refit(&src, 1);
                    build_ms["bvh refit, 1 thread"].push_back(
                        std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
                    bytes_per_tri["bvh refit"] = bytes_per_tri["bvh"];
                }
                sah = b.stats().sah_wide;
                if (t == all) bvh = std::move(b);
                for (auto q : {bench::EmbreeQuality::Medium, bench::EmbreeQuality::High}) {
                    t0 = Clock::now();
                    bench::EmbreeScene es(t == 1 ? device1.device : device_all.device, m, q);
                    build_ms[std::string("embree ") + bench::quality_name(q) + ", " + th].push_back(
                        std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
                    bytes_per_tri[std::string("embree ") + bench::quality_name(q)] =
                        double(es.bytes) / tris;
                }
                if (all == 1) break;
            }
        }
        bench::EmbreeScene medium(device.device, m, bench::EmbreeQuality::Medium);
        bench::EmbreeScene high(device.device, m, bench::EmbreeQuality::High);

        std::printf("## %s (%zu triangles)\n\n", name.c_str(), m.num_triangles());
        std::printf("| build | ms, median (min-max) | bytes/triangle |\n|---|---:|---:|\n");
        nlohmann::json& js = doc["scenes"][name];
        for (const auto& [k, v] : build_ms) {
            const std::string structure = k.substr(0, k.find(','));
            std::printf("| %s | %s | %.1f |\n", k.c_str(), cell(v, 2).c_str(),
                        bytes_per_tri[structure]);
            js["build_ms"][k] = v;
        }
        js["bytes_per_triangle"] = bytes_per_tri;
        js["bvh_sah"] = sah;
        std::printf("\nOur SAH (wide tree, leaf blocks of %zu as one unit): %.2f\n\n",
                    kern::TriangleBvh::kLeafWidth, sah);

        for (const std::string& set : o.sets) {
            const bool occl = set == "shadow", coherent = set == "primary";
            const auto& rays = set == "primary"   ? rs.primary
                               : set == "diffuse" ? rs.diffuse
                                                  : rs.shadow;
            std::vector<bench::TraceForm> forms = bench::our_forms(bvh, rays, occl, coherent);
            const std::size_t n_ours = forms.size();
            for (auto* es : {&medium, &high}) {
                auto e = bench::embree_forms(
                    es->scene,
                    es == &medium ? bench::EmbreeQuality::Medium : bench::EmbreeQuality::High, rays,
                    occl, coherent);
                forms.insert(forms.end(), e.begin(), e.end());
            }
            std::vector<std::vector<double>> mrays(forms.size());
            std::vector<double> vs_e1, best_ratio;
            std::vector<std::size_t> hits(forms.size());
            for (int r = 0; r < o.rounds; ++r) {
                std::vector<double> rate(forms.size());
                for (std::size_t f = 0; f < forms.size(); ++f) {
                    const double s =
                        time_pass(forms[f], rays.size(), arena, threads, o.min_time, hits[f]);
                    rate[f] = double(rays.size()) / s * 1e-6;
                    mrays[f].push_back(rate[f]);
                }
                // Per round: ours (single ray) / E1 at medium quality; best of ours / best of
                // Embree's (any form, any quality).
                vs_e1.push_back(rate[0] / rate[n_ours]);
                const double best_own =
                    *std::max_element(rate.begin(), rate.begin() + long(n_ours));
                const double best_e = *std::max_element(rate.begin() + long(n_ours), rate.end());
                best_ratio.push_back(best_own / best_e);
            }
            std::printf("### %s / %s rays (%zu), million rays/s\n\n", name.c_str(), set.c_str(),
                        rays.size());
            std::printf("| form | Mrays/s, median (min-max) | hits |\n|---|---:|---:|\n");
            for (std::size_t f = 0; f < forms.size(); ++f) {
                std::printf("| %s | %s | %zu |\n", forms[f].name.c_str(), cell(mrays[f], 2).c_str(),
                            hits[f]);
                js["sets"][set]["mrays"][forms[f].name] = mrays[f];
            }
            std::printf("\n- bvh / %s (medium): %s\n", forms[n_ours].name.substr(14).c_str(),
                        cell(vs_e1, 2).c_str());
            std::printf("- best own form / best Embree form: %s\n\n", cell(best_ratio, 2).c_str());
            js["sets"][set]["bvh_vs_e1"] = vs_e1;
            js["sets"][set]["best_own_vs_best_embree"] = best_ratio;
            std::fflush(stdout);
        }
    }
    const std::string load_after = load_average();
    doc["machine"]["load_after"] = load_after;
    std::printf("Load average after: %s\n", load_after.c_str());
    if (!o.json.empty()) std::ofstream(o.json) << doc.dump(1) << "\n";
    return 0;
}
