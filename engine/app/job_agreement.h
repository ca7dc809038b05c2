#pragma once
// Every MPI rank of one render must render the same job: one scene, one resolution, one
// set of settings. A rank started with another --width, scene, seed or integrator would
// otherwise add its share to a silently mixed image, or wait forever in a collective the
// others never call (path on one rank, SPPM on another). The ranks compare what they loaded
// before the render's first collective.
#include <string>
#include <utility>
#include <vector>

#include "engine/core/cluster.h"
#include "render_job.h"

namespace foton::app {

// What must agree, as named lines: {"width", "128"}, {"scene file", "<path> fnv1a 3f…"}, ...
using JobFingerprint = std::vector<std::pair<std::string, std::string>>;

// The job as this rank loaded it: the scene file's bytes and geometry, the film, the camera,
// every renderer setting as used, the samples, passes, time budget, seed and accelerator.
// Threads and pinning are left out: nodes may differ in cores.
JobFingerprint job_fingerprint(const std::string& scene_path, const RenderJob& job);

// Collective: every rank's fingerprint against rank 0's. Throws InputError (the same message
// on every rank) naming the first rank and line that differ.
void agree_on_job(const Cluster& ranks, const JobFingerprint& mine, const std::string& scene_path);

}  // namespace foton::app
