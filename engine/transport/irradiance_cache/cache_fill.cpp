#include "cache_fill.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "engine/core/thread_pinning.h"
#include "engine/transport/irradiance_cache/cache_evaluator.h"

namespace foton {

namespace {
constexpr std::size_t kChunk = 64;  // pixels per job of a pass
}

uint32_t fill_irradiance_cache(const Scene& scene, const CameraIntegrator& integrator,
                               std::vector<IrradianceCache>& caches, uint32_t spp, int threads,
                               RenderStats& stats, StageGraph& graph,
                               const std::vector<uint32_t>& after, const Cluster* cluster,
                               const std::atomic<bool>* cancel) {
    const Cluster& ranks = cluster_or_solo(cluster);
    const int w = scene.film.width, h = scene.film.height;
    const uint64_t npix = uint64_t(w) * uint64_t(h);
    std::vector<uint8_t> visited(npix, 0);
    struct Scratch {
        std::unique_ptr<IntegratorWorkspace> ws;
        std::vector<RGB> out;
        RenderStats stats;
    };
    tbb::enumerable_thread_specific<Scratch> scratch;
    PinnedArena arena(threads);
    // A pass as two graph nodes: the pass's pixels traced in parallel chunks against the
    // frozen caches, then the chunks' new records inserted in chunk order.
    std::vector<SampleJob> jobs;
    using ChunkRecords = std::vector<std::vector<IrradianceRecord>>;  // [level]
    std::vector<ChunkRecords> found;                                  // [chunk]
    // Across MPI ranks the chunks are dealt out in turn (chunk c to rank c mod N: the image's
    // top and bottom need very different numbers of new records); the new records of all
    // are exchanged, and every rank inserts them in chunk order.
    const std::size_t ranks_n = std::size_t(ranks.size()), rank = std::size_t(ranks.rank());
    auto mine = [&](std::size_t chunks) { return (chunks + ranks_n - 1 - rank) / ranks_n; };
    const uint32_t records = graph.add("cache-fill-records", [&]() -> uint64_t {
        const std::size_t chunks = (jobs.size() + kChunk - 1) / kChunk;
        found.assign(chunks, {});
        const ProgressTask task(graph.progress(), "cache-fill-records", mine(chunks));
        std::atomic<uint64_t> traced{0};
        tbb::parallel_for(
            tbb::blocked_range<std::size_t>(0, mine(chunks), 1),
            [&](const tbb::blocked_range<std::size_t>& r) {
                Scratch& s = scratch.local();
                if (!s.ws) s.ws = integrator.make_workspace();
                for (std::size_t k = r.begin(); k != r.end(); ++k) {
                    // A cancelled fill computes no further record (its chunks stay empty).
                    if (cancel && cancel->load(std::memory_order_relaxed)) return;
                    const std::size_t c = rank + k * ranks_n;
                    const std::vector<SampleJob> part(
                        jobs.begin() + std::ptrdiff_t(c * kChunk),
                        jobs.begin() + std::ptrdiff_t(std::min(jobs.size(), (c + 1) * kChunk)));
                    integrator.trace(part, *s.ws, s.out, s.stats);
                    traced += part.size();
                    for (CacheLevelWork& l : s.ws->cache_workspace()->levels) {
                        found[c].emplace_back();
                        for (std::size_t i = 0; i < l.found->size(); ++i)
                            found[c].back().push_back(l.found->record(i));
                    }
                    task.advance();
                }
            });
        return traced.load();
    });
    const uint32_t insert = graph.add("cache-fill-insert", [&]() -> uint64_t {
        uint64_t n = 0;
        auto insert_chunk = [&](const ChunkRecords& chunk) {
            for (std::size_t l = 0; l < chunk.size(); ++l) {
                for (const IrradianceRecord& rec : chunk[l]) caches[l].insert(rec);
                n += chunk[l].size();
            }
        };
        if (!ranks.distributed()) {
            for (const ChunkRecords& chunk : found) insert_chunk(chunk);
            return n;
        }
        Bytes packed;
        for (std::size_t c = rank; c < found.size(); c += ranks_n) {
            pack_value(packed, uint64_t(found[c].size()));
            for (const std::vector<IrradianceRecord>& level : found[c]) pack(packed, level);
        }
        const std::vector<Bytes> parts = ranks.all_gather(packed);
        std::vector<Unpacker> from(parts.begin(), parts.end());
        for (std::size_t c = 0; c < found.size(); ++c) {
            Unpacker& in = from[c % ranks_n];
            ChunkRecords chunk(in.value<uint64_t>());
            for (std::vector<IrradianceRecord>& level : chunk) in.append(level);
            insert_chunk(chunk);
        }
        return n;
    });
    graph.edge(records, insert);
    for (uint32_t a : after) graph.edge(a, records);
    const int extent = std::max(w, h) - 1;
    for (int level = 0;; ++level) {
        // Grid points round(i (size - 1) / 2^level): both image edges at every level.
        const int steps = 1 << level;
        jobs.clear();
        for (int iy = 0; iy <= steps; ++iy) {
            const int y = int(std::lround(double(iy) * (h - 1) / steps));
            for (int ix = 0; ix <= steps; ++ix) {
                const int x = int(std::lround(double(ix) * (w - 1) / steps));
                const uint64_t pixel = uint64_t(y) * uint64_t(w) + uint64_t(x);
                if (visited[pixel]) continue;
                visited[pixel] = 1;
                jobs.push_back({uint32_t(x), uint32_t(y), 0, spp, 0, pixel * spp});
            }
        }
        if (!jobs.empty()) graph.run(arena, {records, insert});
        if (steps >= extent) break;
        // Across ranks every rank runs every level (the exchanges are collective).
        if (cancel && cancel->load() && !ranks.distributed()) break;
    }
    for (Scratch& s : scratch) {
        // The fill's lookups are not the image's: keep its work, not its lookup counts.
        s.stats.cache = {};
        stats.merge(s.stats);
    }
    return insert;
}

}  // namespace foton
