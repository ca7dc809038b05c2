#pragma once
// Filling the irradiance cache before the image pass, in hierarchical pixel order (the
// lecture notes): the first pass visits the image's corners, each further pass the points of
// a grid twice as fine (skipping those visited), down to every pixel. Records therefore
// spread evenly instead of piling up along the first scanlines.
//
// Parallel and deterministic (DESIGN.md): a pass traces its pixels in fixed chunks on all
// threads, every chunk reading the cache as the previous pass left it (frozen); the chunks'
// new records are then inserted in chunk order. Chunks of one pass may compute overlapping
// records (they cannot see each other's): the price of the parallelism, counted in the
// statistics as records per pixel.
#include <atomic>
#include <functional>

#include "engine/core/cluster.h"
#include "engine/core/stats.h"
#include "engine/scene/scene.h"
#include "engine/transport/common/camera_integrator.h"
#include "engine/transport/irradiance_cache/irradiance_cache.h"
#include "engine/transport/run/stage_graph.h"

namespace foton {

// Fills `caches` (one per level) through `integrator`, whose cache evaluator reads them.
// `spp` is the image pass's samples per pixel: the fill traces sample 0 of pass 0 of every
// pixel, the very sample the image pass will trace first.
// Each pass runs as the graph's nodes cache-fill-records -> cache-fill-insert (after the
// nodes `after`); returns the last, for the camera pass to follow. Across the MPI ranks of
// `cluster` the passes are split and every rank ends with the same caches.
uint32_t fill_irradiance_cache(const Scene& scene, const CameraIntegrator& integrator,
                               std::vector<IrradianceCache>& caches, uint32_t spp, int threads,
                               RenderStats& stats, StageGraph& graph,
                               const std::vector<uint32_t>& after, const Cluster* cluster = nullptr,
                               const std::atomic<bool>* cancel = nullptr);

}  // namespace foton
