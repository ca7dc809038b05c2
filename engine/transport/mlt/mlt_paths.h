#pragma once
// What a Markov chain of primary-sample vectors is a chain of (mlt.h): the paths that turn a
// vector into light on the image. A vector's sample deposits one or more contributions
// (pixel, radiance); the target f of the chain is the sum of their luminances. Two kinds:
//   - path: the path tracer's path (one contribution: its film position's pixel);
//   - bdpt: a camera subpath and a light subpath with every bidirectional strategy between
//     them, MIS-weighted as the bdpt integrator weighs them (Kelemen et al. 2002's MLT over
//     bidirectional paths): the camera path's estimate at its pixel and the light path's
//     joins to the camera wherever they land.
// Both evaluate a batch of vectors at once (one wavefront through their integrator's code).
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/core/stats.h"
#include "engine/transport/common/primary_vector.h"
#include "engine/transport/run/render_context.h"

namespace foton {

struct MltContribution {
    uint32_t pixel = 0;
    RGB value;
};

// A batch of vectors and, once evaluated, what each deposits: vector i's contributions are
// contrib[first[i] .. first[i + 1]), f[i] the sum of their luminances (negative ones: 0).
struct MltBatch {
    std::vector<PrimaryVector*> v;
    std::vector<uint64_t> keys;  // each vector's key (numbers past its end)
    std::vector<float> f;
    std::vector<uint32_t> first;
    std::vector<MltContribution> contrib;
    std::size_t size() const { return v.size(); }
    void clear_results() {
        f.clear();
        first.assign(1, 0);
        contrib.clear();
    }
    // Vector i's deposits end here (after its contributions were pushed).
    void close(std::size_t i) {
        float sum = 0.f;
        for (uint32_t k = first[i]; k < uint32_t(contrib.size()); ++k)
            sum += std::max(0.f, contrib[k].value.luminance());
        f.push_back(sum);
        first.push_back(uint32_t(contrib.size()));
    }
};

// A thread's buffers for one kind of paths.
struct MltScratch {
    virtual ~MltScratch() = default;
    RenderStats stats;
};

class MltPaths {
  public:
    virtual ~MltPaths() = default;
    virtual uint32_t dims() const = 0;  // numbers a vector holds (more are drawn fresh)
    virtual std::unique_ptr<MltScratch> make_scratch() const = 0;
    virtual void evaluate(MltBatch& b, MltScratch& s) const = 0;
};

std::unique_ptr<MltPaths> make_path_mlt_paths(const RenderContext& ctx);
// Fails (InputError) where bdpt would: no perspective camera, no light.
std::unique_ptr<MltPaths> make_bidir_mlt_paths(const RenderContext& ctx);

}  // namespace foton
