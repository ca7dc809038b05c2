// Google Benchmark: ray traversal of the kernel scenes (bench/ray_sets.h), our uniform grid
// (kernels/) against raw Embree on identical rays, single thread and all threads:
//   intersect: grid single ray (with and without mailbox), grid coherent packets (primary rays;
//              4x4, 8x8 and 16x16 pixel bundles), the wide BVH single ray in its engine shape
//              and the width study's shapes (bvh4x4, bvh8x4, bvh16x4), BVH packets of W
//              consecutive rays (primary), rtcIntersect1, rtcIntersect8 / 16 (packets of
//              consecutive rays: 4x2 / 4x4 pixels for primary rays), rtcIntersect1M and
//              rtcIntersectNp streams of 4,096 rays (flagged coherent for primary rays only);
//   occlusion: grid and BVH any-hit, rtcOccluded1 / 8 / 16 (shadow rays);
//   build:     grid (one thread) and BVH (one thread, all threads) against Embree's default
//              build on all threads and on one.
// Every form resets each ray's tmax and hit before it is traced, inside the timed loop.
// Names: traversal/<scene>/<set>/<method>/threads:<n>; bench/report makes the ratio tables.
#include <benchmark/benchmark.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <map>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "bench/ray_sets.h"
#include "bench/trace_forms.h"
#include "kernels/triangle_bvh.h"
#include "kernels/triangle_kdtree.h"
#include "kernels/triangle_octree.h"
#include "kernels/uniform_grid.h"

using namespace foton;
using foton::kern::Ray1;

namespace {

constexpr std::size_t kChunk = 4096;  // rays per task and per stream call
constexpr std::size_t W = kern::kBlockWidth;

// The wide BVH shapes of the width study (N children per node x M triangles per leaf block);
// kern::TriangleBvh is the one the engine uses.
using Bvh4x4 = kern::TriangleBvhT<4, 4>;
#if defined(__AVX__)
using Bvh8x4 = kern::TriangleBvhT<8, 4>;
#endif
#if defined(__AVX512BW__)
using Bvh16x4 = kern::TriangleBvhT<16, 4>;
#endif

kern::BvhBuildParams::ParallelInvoke tbb_invoke() {
    return [](const std::function<void()>& a, const std::function<void()>& b) {
        tbb::parallel_invoke(a, b);
    };
}

template <class Bvh>
Bvh build_bvh(const TriangleMesh& m, bool parallel) {
    auto p = Bvh::default_params();
    if (parallel) p.parallel = tbb_invoke();
    Bvh b;
    b.build(m.positions.data(), m.indices.data(), m.num_triangles(), p);
    return b;
}

struct SceneData {
    bench::KernelScene scene;
    bench::RaySets sets;
    kern::UniformGrid grid, grid_mailbox;
    kern::TriangleOctree octree;
    kern::TriangleKdTree kdtree;
    kern::TriangleBvh bvh;
    Bvh4x4 bvh4x4;
#if defined(__AVX__)
    Bvh8x4 bvh8x4;
#endif
#if defined(__AVX512BW__)
    Bvh16x4 bvh16x4;
#endif
    std::unique_ptr<bench::EmbreeDevice> device;  // declared first: outlives the scene
    bench::EmbreeScene rtc;                       // Embree's default (medium) build
};

SceneData& scene_data(const std::string& name) {
    static std::map<std::string, std::unique_ptr<SceneData>> all;
    auto& slot = all[name];
    if (slot) return *slot;
    // One scene at a time: the dragon's sets and both structures are large.
    all.clear();
    auto d = std::make_unique<SceneData>();
    d->scene = bench::load_kernel_scene(name);
    d->sets = bench::make_ray_sets(d->scene, 1024, 1u << 18);
    const TriangleMesh& m = d->scene.mesh;
    d->grid.build(m.positions.data(), m.indices.data(), m.num_triangles());
    kern::GridParams mailbox;
    mailbox.mailbox = true;
    d->grid_mailbox.build(m.positions.data(), m.indices.data(), m.num_triangles(), mailbox);
    d->octree.build(m.positions.data(), m.indices.data(), m.num_triangles());
    d->kdtree.build(m.positions.data(), m.indices.data(), m.num_triangles());
    d->bvh = build_bvh<kern::TriangleBvh>(m, true);
    d->bvh4x4 = build_bvh<Bvh4x4>(m, true);
#if defined(__AVX__)
    d->bvh8x4 = build_bvh<Bvh8x4>(m, true);
#endif
#if defined(__AVX512BW__)
    d->bvh16x4 = build_bvh<Bvh16x4>(m, true);
#endif
    d->device = std::make_unique<bench::EmbreeDevice>(0);
    d->rtc = bench::EmbreeScene(d->device->device, m, bench::EmbreeQuality::Medium);
    return *(all[name] = std::move(d));
}

const std::vector<Ray1>& ray_set(SceneData& d, const std::string& set) {
    return set == "primary" ? d.sets.primary : set == "diffuse" ? d.sets.diffuse : d.sets.shadow;
}

// Runs f(begin, end) over [0, n) in chunks, on this thread or on all of them.
template <class F>
void for_chunks(std::size_t n, std::size_t chunk, bool parallel, F&& f) {
    if (!parallel) {
        for (std::size_t b = 0; b < n; b += chunk) f(b, std::min(n, b + chunk));
        return;
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, (n + chunk - 1) / chunk, 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t c = r.begin(); c < r.end(); ++c)
                              f(c * chunk, std::min(n, (c + 1) * chunk));
                      });
}

void report(benchmark::State& state, std::size_t rays, std::size_t hits) {
    state.counters["rays/s"] =
        benchmark::Counter(double(rays), benchmark::Counter::kIsIterationInvariantRate);
    state.counters["hit%"] = 100.0 * double(hits) / double(rays) / double(state.iterations());
}

// report() and the BVH's work per ray: nodes tested and triangle lanes (blocks x leaf width).
void report_bvh(benchmark::State& state, std::size_t rays, std::size_t hits, uint64_t nodes,
                uint64_t blocks, std::size_t leaf_width) {
    report(state, rays, hits);
    const double traced = double(rays) * double(state.iterations());
    state.counters["nodes/ray"] = double(nodes) / traced;
    state.counters["tris/ray"] = double(blocks) * double(leaf_width) / traced;
}

// Counts hits across threads.
struct HitCount {
    std::atomic<std::size_t> n{0};
    void add(std::size_t k) { n.fetch_add(k, std::memory_order_relaxed); }
};

// ---- our grid -------------------------------------------------------------------------

void BM_GridImpl(benchmark::State& state, const std::string& scene, const std::string& set,
                 bool par, bool mailbox) {
    SceneData& d = scene_data(scene);
    const kern::UniformGrid& grid = mailbox ? d.grid_mailbox : d.grid;
    const auto& rays = ray_set(d, set);
    const bool occl = set == "shadow";
    HitCount hits;
    for (auto _ : state)
        for_chunks(rays.size(), kChunk, par, [&](std::size_t b, std::size_t e) {
            std::size_t h = 0;
            for (std::size_t i = b; i < e; ++i) {
                if (occl) {
                    h += grid.occluded(rays[i]);
                } else {
                    kern::TriHit hit;
                    h += grid.intersect(rays[i], hit);
                }
            }
            hits.add(h);
        });
    report(state, rays.size(), hits.n);
}

void BM_Grid(benchmark::State& state, std::string scene, std::string set, bool par) {
    BM_GridImpl(state, scene, set, par, false);
}
void BM_GridMailbox(benchmark::State& state, std::string scene, std::string set, bool par) {
    BM_GridImpl(state, scene, set, par, true);
}

// ---- our octree and kd-tree ---------------------------------------------------------------

template <class Tree, Tree SceneData::*member>
void BM_Tree(benchmark::State& state, std::string scene, std::string set, bool par) {
    SceneData& d = scene_data(scene);
    const Tree& tree = d.*member;
    const auto& rays = ray_set(d, set);
    const bool occl = set == "shadow";
    HitCount hits;
    std::atomic<uint64_t> nodes{0}, blocks{0};
    for (auto _ : state)
        for_chunks(rays.size(), kChunk, par, [&](std::size_t b, std::size_t e) {
            std::size_t h = 0;
            kern::TreeCounters c;
            for (std::size_t i = b; i < e; ++i) {
                if (occl) {
                    h += tree.occluded(rays[i], &c);
                } else {
                    kern::TriHit hit;
                    h += tree.intersect(rays[i], hit, &c);
                }
            }
            hits.add(h);
            nodes += c.nodes;
            blocks += c.blocks;
        });
    report_bvh(state, rays.size(), hits.n, nodes, blocks, kern::kBlockWidth);
}

// Primary rays in bundles of `side` x `side` pixels (side^2 / W packets of W rays).
void BM_GridPacket(benchmark::State& state, std::string scene, std::size_t side, bool par) {
    SceneData& d = scene_data(scene);
    const auto& rays = d.sets.primary;
    const std::size_t bundle = side * side, np = bundle / W;
    std::vector<kern::RayPacket> packets(rays.size() / W);
    for (std::size_t p = 0; p < packets.size(); ++p)
        for (std::size_t l = 0; l < W; ++l) {
            const Ray1& r = rays[p * W + l];
            kern::RayPacket& k = packets[p];
            k.ox[l] = r.ox, k.oy[l] = r.oy, k.oz[l] = r.oz;
            k.dx[l] = r.dx, k.dy[l] = r.dy, k.dz[l] = r.dz, k.tmin[l] = r.tmin;
        }
    HitCount hits;
    for (auto _ : state)
        for_chunks(rays.size(), kChunk, par, [&](std::size_t b, std::size_t e) {
            std::size_t h = 0;
            for (std::size_t i = b; i < e; i += bundle) {
                kern::PacketHits ph[kern::kMaxGridPackets];
                for (std::size_t p = 0; p < np; ++p)
                    for (std::size_t l = 0; l < W; ++l) {
                        ph[p].t[l] = rays[i + p * W + l].tmax;
                        ph[p].id[l] = kern::kInvalidId;
                    }
                d.grid.intersect_packets(&packets[i / W], np, ph);
                for (std::size_t p = 0; p < np; ++p)
                    for (std::size_t l = 0; l < W; ++l) h += ph[p].id[l] != kern::kInvalidId;
            }
            hits.add(h);
        });
    report(state, rays.size(), hits.n);
}

// ---- our wide BVH ----------------------------------------------------------------------

template <class Bvh>
void BM_BvhImpl(benchmark::State& state, const Bvh& bvh, const std::vector<Ray1>& rays, bool occl,
                bool par) {
    HitCount hits;
    std::atomic<uint64_t> nodes{0}, blocks{0};
    for (auto _ : state)
        for_chunks(rays.size(), kChunk, par, [&](std::size_t b, std::size_t e) {
            std::size_t h = 0;
            kern::BvhCounters c;
            for (std::size_t i = b; i < e; ++i) {
                if (occl) {
                    h += bvh.occluded(rays[i], &c);
                } else {
                    kern::TriHit hit;
                    h += bvh.intersect(rays[i], hit, &c);
                }
            }
            hits.add(h);
            nodes.fetch_add(c.nodes, std::memory_order_relaxed);
            blocks.fetch_add(c.blocks, std::memory_order_relaxed);
        });
    report_bvh(state, rays.size(), hits.n, nodes, blocks, Bvh::kLeafWidth);
}

// The packet form: W consecutive rays per packet (a 4x4 pixel square of primary rays on
// AVX-512, see ray_sets.h), all active.
void BM_BvhPacket(benchmark::State& state, std::string scene, std::string set, bool par) {
    SceneData& d = scene_data(scene);
    const auto& rays = ray_set(d, set);
    const bool occl = set == "shadow";
    const std::size_t np = (rays.size() + W - 1) / W;
    std::vector<kern::RayPacket> packets(np);
    std::vector<std::array<float, W>> tmax(np);
    std::vector<uint32_t> active(np, 0);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Ray1& r = rays[i];
        kern::RayPacket& k = packets[i / W];
        const std::size_t l = i % W;
        k.ox[l] = r.ox, k.oy[l] = r.oy, k.oz[l] = r.oz;
        k.dx[l] = r.dx, k.dy[l] = r.dy, k.dz[l] = r.dz, k.tmin[l] = r.tmin;
        tmax[i / W][l] = r.tmax;
        active[i / W] |= 1u << l;
    }
    HitCount hits;
    std::atomic<uint64_t> nodes{0}, blocks{0};
    for (auto _ : state)
        for_chunks(np, kChunk / W, par, [&](std::size_t b, std::size_t e) {
            std::size_t h = 0;
            kern::BvhCounters c;
            for (std::size_t p = b; p < e; ++p) {
                if (occl) {
                    h += std::size_t(__builtin_popcount(
                        d.bvh.occluded_packet(packets[p], tmax[p].data(), active[p], &c)));
                    continue;
                }
                kern::PacketHits ph;
                for (std::size_t l = 0; l < W; ++l)
                    ph.t[l] = tmax[p][l], ph.id[l] = kern::kInvalidId;
                d.bvh.intersect_packet(packets[p], active[p], ph, &c);
                for (std::size_t l = 0; l < W; ++l) h += ph.id[l] != kern::kInvalidId;
            }
            hits.add(h);
            nodes.fetch_add(c.nodes, std::memory_order_relaxed);
            blocks.fetch_add(c.blocks, std::memory_order_relaxed);
        });
    report_bvh(state, rays.size(), hits.n, nodes, blocks, kern::TriangleBvh::kLeafWidth);
}

// The stream form: each chunk of kChunk rays (the size Embree's streams get) in one call,
// from SoA columns as the engine's RayBatch holds them.
void BM_BvhStream(benchmark::State& state, std::string scene, std::string set, bool par) {
    SceneData& d = scene_data(scene);
    const auto& rays = ray_set(d, set);
    const bool occl = set == "shadow";
    bench::RayColumns cols(rays);
    HitCount hits;
    std::atomic<uint64_t> nodes{0}, blocks{0};
    for (auto _ : state)
        for_chunks(rays.size(), kChunk, par, [&](std::size_t b, std::size_t e) {
            std::size_t h = 0;
            kern::BvhCounters c;
            if (occl) {
                d.bvh.occluded_stream(cols.rays(b, e), &cols.occluded[b], &c);
                for (std::size_t i = b; i < e; ++i) h += cols.occluded[i];
            } else {
                d.bvh.intersect_stream(cols.rays(b, e), cols.hits(b), &c);
                for (std::size_t i = b; i < e; ++i) h += cols.id[i] != kern::kInvalidId;
            }
            hits.add(h);
            nodes.fetch_add(c.nodes, std::memory_order_relaxed);
            blocks.fetch_add(c.blocks, std::memory_order_relaxed);
        });
    report_bvh(state, rays.size(), hits.n, nodes, blocks, kern::TriangleBvh::kLeafWidth);
}

template <class Bvh, Bvh SceneData::*member>
void BM_Bvh(benchmark::State& state, std::string scene, std::string set, bool par) {
    SceneData& d = scene_data(scene);
    BM_BvhImpl(state, d.*member, ray_set(d, set), set == "shadow", par);
}

// ---- Embree ---------------------------------------------------------------------------

// Embree's forms (bench/trace_forms.h: rtcIntersect1 / rtcOccluded1, packets of 8 and 16,
// the 1M and Np streams) on the scene's medium-quality BVH, by the form's name suffix.
constexpr const char* kEmbreeForms[] = {"1", "8", "16", "1M", "Np"};

template <int Form>
void BM_Embree(benchmark::State& state, std::string scene, std::string set, bool par) {
    SceneData& d = scene_data(scene);
    const auto& rays = ray_set(d, set);
    const bool occl = set == "shadow";
    const auto forms = bench::embree_forms(d.rtc.scene, bench::EmbreeQuality::Medium, rays, occl,
                                           set == "primary");
    const std::string name =
        std::string(occl ? "rtcOccluded" : "rtcIntersect") + kEmbreeForms[Form];
    const auto form = std::find_if(forms.begin(), forms.end(), [&](const bench::TraceForm& f) {
        return f.name.size() >= name.size() &&
               f.name.compare(f.name.size() - name.size(), name.size(), name) == 0;
    });
    HitCount hits;
    for (auto _ : state)
        for_chunks(rays.size(), kChunk, par,
                   [&](std::size_t b, std::size_t e) { hits.add(form->run(b, e)); });
    report(state, rays.size(), hits.n);
}

// ---- build ----------------------------------------------------------------------------

void BM_BuildGrid(benchmark::State& state, std::string scene) {
    const TriangleMesh& m = scene_data(scene).scene.mesh;
    for (auto _ : state) {
        kern::UniformGrid g;
        g.build(m.positions.data(), m.indices.data(), m.num_triangles());
        benchmark::DoNotOptimize(g.num_blocks());
    }
    state.counters["tris/s"] = benchmark::Counter(double(m.num_triangles()),
                                                  benchmark::Counter::kIsIterationInvariantRate);
    state.counters["nested_grids"] = double(scene_data(scene).grid.num_child_grids());
}

// Octree and kd-tree builds: time, memory, references per triangle, size, depth (and the
// kd-tree's SAH cost).
template <class Tree>
void BM_BuildTree(benchmark::State& state, std::string scene, bool parallel) {
    const TriangleMesh& m = scene_data(scene).scene.mesh;
    std::size_t bytes = 0, refs = 0, nodes = 0;
    int depth = 0;
    double sah = 0.0;
    for (auto _ : state) {
        Tree t;
        if constexpr (std::is_same_v<Tree, kern::TriangleKdTree>) {
            kern::KdTreeParams p;
            if (parallel) p.parallel = tbb_invoke();
            t.build(m.positions.data(), m.indices.data(), m.num_triangles(), p);
        } else {
            t.build(m.positions.data(), m.indices.data(), m.num_triangles());
        }
        bytes = t.memory_bytes(), refs = t.num_references(), nodes = t.num_nodes();
        depth = t.depth();
        if constexpr (requires { t.sah_cost(); }) sah = t.sah_cost();
        benchmark::DoNotOptimize(t.num_nodes());
    }
    state.counters["tris/s"] = benchmark::Counter(double(m.num_triangles()),
                                                  benchmark::Counter::kIsIterationInvariantRate);
    state.counters["bytes/tri"] = double(bytes) / double(m.num_triangles());
    state.counters["refs/tri"] = double(refs) / double(m.num_triangles());
    state.counters["nodes"] = double(nodes);
    state.counters["depth"] = depth;
    if (sah > 0.0) state.counters["sah"] = sah;
}

template <class Bvh>
void BM_BuildBvh(benchmark::State& state, std::string scene, bool parallel) {
    const TriangleMesh& m = scene_data(scene).scene.mesh;
    std::size_t bytes = 0;
    double sah = 0.0;
    for (auto _ : state) {
        const Bvh b = build_bvh<Bvh>(m, parallel);
        bytes = b.memory_bytes();
        sah = b.stats().sah_wide;
        benchmark::DoNotOptimize(b.root());
    }
    state.counters["tris/s"] = benchmark::Counter(double(m.num_triangles()),
                                                  benchmark::Counter::kIsIterationInvariantRate);
    state.counters["bytes/tri"] = double(bytes) / double(m.num_triangles());
    state.counters["sah"] = sah;
}

void BM_BuildEmbree(benchmark::State& state, std::string scene, bool one_thread) {
    const TriangleMesh& m = scene_data(scene).scene.mesh;
    const bench::EmbreeDevice dev(one_thread ? 1 : 0);
    for (auto _ : state) {
        const bench::EmbreeScene s(dev.device, m, bench::EmbreeQuality::Medium);
        benchmark::DoNotOptimize(s.scene);
    }
    state.counters["tris/s"] = benchmark::Counter(double(m.num_triangles()),
                                                  benchmark::Counter::kIsIterationInvariantRate);
}

const bool registered = [] {
    using Fn = void (*)(benchmark::State&, std::string, std::string, bool);
    // The BVH shapes run on every ray set: the engine's and the width study's.
    const std::pair<const char*, Fn> bvh_shapes[] = {
        {"bvh", BM_Bvh<kern::TriangleBvh, &SceneData::bvh>}, {"bvh_stream", BM_BvhStream},
        {"bvh4x4", BM_Bvh<Bvh4x4, &SceneData::bvh4x4>},
#if defined(__AVX__)
        {"bvh8x4", BM_Bvh<Bvh8x4, &SceneData::bvh8x4>},
#endif
#if defined(__AVX512BW__)
        {"bvh16x4", BM_Bvh<Bvh16x4, &SceneData::bvh16x4>},
#endif
    };
    const std::pair<const char*, Fn> intersect[] = {
        {"grid", BM_Grid},
        {"grid_mailbox", BM_GridMailbox},
        {"octree", BM_Tree<kern::TriangleOctree, &SceneData::octree>},
        {"kdtree", BM_Tree<kern::TriangleKdTree, &SceneData::kdtree>},
        {"embree_rtcIntersect1", BM_Embree<0>},
        {"embree_rtcIntersect8", BM_Embree<1>},
        {"embree_rtcIntersect16", BM_Embree<2>},
        {"embree_rtcIntersect1M", BM_Embree<3>},
        {"embree_rtcIntersectNp", BM_Embree<4>},
    };
    const std::pair<const char*, Fn> occlusion[] = {
        {"grid", BM_Grid},
        {"octree", BM_Tree<kern::TriangleOctree, &SceneData::octree>},
        {"kdtree", BM_Tree<kern::TriangleKdTree, &SceneData::kdtree>},
        {"embree_rtcOccluded1", BM_Embree<0>},
        {"embree_rtcOccluded8", BM_Embree<1>},
        {"embree_rtcOccluded16", BM_Embree<2>},
    };
    auto add = [](const std::string& name, auto&&... args) {
        benchmark::RegisterBenchmark(name.c_str(), args...)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
    };
    const int all = tbb::this_task_arena::max_concurrency();
    for (const char* scene : {"bunny", "teapot", "dragon", "cornell", "stadium"}) {
        const std::string s = scene;
        add("build/" + s + "/grid", BM_BuildGrid, s);
        add("build/" + s + "/octree", BM_BuildTree<kern::TriangleOctree>, s, false);
        add("build/" + s + "/kdtree", BM_BuildTree<kern::TriangleKdTree>, s, false);
        add("build/" + s + "/kdtree_parallel", BM_BuildTree<kern::TriangleKdTree>, s, true);
        add("build/" + s + "/bvh_1thread", BM_BuildBvh<kern::TriangleBvh>, s, false);
        add("build/" + s + "/bvh", BM_BuildBvh<kern::TriangleBvh>, s, true);
        add("build/" + s + "/embree", BM_BuildEmbree, s, false);
        add("build/" + s + "/embree_1thread", BM_BuildEmbree, s, true);
        for (bool par : {false, true}) {
            const std::string th = "/threads:" + std::to_string(par ? all : 1);
            for (const char* set : {"primary", "diffuse", "shadow"})
                for (const auto& [method, fn] : bvh_shapes)
                    add("traversal/" + s + "/" + set + "/" + method + th, fn, s, set, par);
            for (const char* set : {"primary", "diffuse"}) {
                for (const auto& [method, fn] : intersect)
                    add("traversal/" + s + "/" + set + "/" + method + th, fn, s, set, par);
                // Packets only where rays are coherent: on the scattered diffuse and shadow sets
                // every packet falls back to single rays (bvh_packet.h).
                if (std::string(set) == "primary")
                    add("traversal/" + s + "/primary/bvh_packet" + th, BM_BvhPacket, s, set, par);
                if (std::string(set) == "primary")
                    for (std::size_t side : {4, 8, 16})
                        if (side * side >= W && side * side / W <= kern::kMaxGridPackets)
                            add("traversal/" + s + "/primary/grid_packet" + std::to_string(side) +
                                    "x" + std::to_string(side) + th,
                                BM_GridPacket, s, side, par);
            }
            for (const auto& [method, fn] : occlusion)
                add("traversal/" + s + "/shadow/" + method + th, fn, s, "shadow", par);
        }
    }
    return true;
}();

}  // namespace
