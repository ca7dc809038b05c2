#pragma once
// The pixel accumulator every family adds its estimates to: per pixel a radiance sum and the
// number of samples in it. Camera samples go to their own pixel; light paths' splats are
// added chunk by chunk in chunk order, so the sums do not depend on which thread traced
// which chunk. Across MPI ranks each pixel has an owner (pixel_owners.h) that adds
// everything it gets, and gather() copies the owners' pixels to rank 0, so the image there
// equals one process's bit for bit.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/core/cluster.h"
#include "engine/core/rgb.h"
#include "engine/film/pixel_owners.h"
#include "film.h"

namespace foton {

// What one light path sends to a film pixel (light tracing; BDPT's and VCM's t = 1 paths).
struct Splat {
    uint32_t pixel;
    RGB value;
};

class PixelSums {
  public:
    PixelSums(int width, int height);
    // Across MPI ranks: the rank that adds to each pixel. Without owners (the default) rank 0
    // adds every splat and gather() has nothing to do.
    void set_owners(PixelOwners owners) { owners_ = std::move(owners); }
    const PixelOwners& owners() const { return owners_; }

    // One pixel's estimate of `samples` samples (threads may add to different pixels at once).
    void add(std::size_t pixel, const RGB& value, uint32_t samples = 1) {
        sum_[pixel] += value;
        count_[pixel] += samples;
    }
    // The splats of this rank's chunks [mine.begin, mine.end), in chunk order, added by their
    // pixels' owners (or by rank 0 without owners): ranks exchange theirs, and each adds them
    // in rank order, which is chunk order as the shares are contiguous. Collective across
    // ranks. Returns how many this rank added.
    std::size_t add_splats(const std::vector<std::vector<Splat>>& chunks, Share mine,
                           const Cluster& cluster);
    // On rank 0, every pixel's sum and count from its owner (owned pixels untouched).
    // Collective across ranks.
    void gather(const Cluster& cluster);

    // The image as each pixel's mean (sum / samples; black where there are none) ...
    Film mean() const;
    // ... or as the sums times one factor (splats: the paths traced are the samples of every
    // pixel at once).
    Film scaled(float factor) const;
    const std::vector<uint32_t>& samples() const { return count_; }
    std::size_t size() const { return sum_.size(); }

  private:
    int width_, height_;
    std::vector<RGB> sum_;
    std::vector<uint32_t> count_;
    PixelOwners owners_;
};

}  // namespace foton
