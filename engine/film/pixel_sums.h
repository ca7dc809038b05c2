#pragma once
// The pixel accumulator every family adds its estimates to: per pixel a radiance sum and the
// number of samples in it. Camera samples go to their own pixel; light paths' splats are
// added chunk by chunk in chunk order, so the sums do not depend on which thread traced
// which chunk. Across MPI ranks each pixel has an owner (pixel_owners.h) that adds
// everything it gets, and gather() copies the owners' pixels to rank 0, so the image there
// equals one process's bit for bit.
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "engine/core/cluster.h"
#include "engine/core/rgb.h"
#include "engine/film/aov.h"
#include "engine/film/pixel_owners.h"
#include "film.h"

namespace foton {

// The sums of a pixel's sample values and of their squares, per channel, in double: what the
// variance AOV needs (a float sum of squares loses the variance of a bright pixel to rounding).
struct SampleMoments {
    std::array<double, 3> sum{}, sum2{};
    void add(const RGB& v) {
        const double c[3] = {double(v.r), double(v.g), double(v.b)};
        for (int k = 0; k < 3; ++k) {
            sum[std::size_t(k)] += c[k];
            sum2[std::size_t(k)] += c[k] * c[k];
        }
    }
    void add(const SampleMoments& m) {
        for (std::size_t k = 0; k < 3; ++k) {
            sum[k] += m.sum[k];
            sum2[k] += m.sum2[k];
        }
    }
};

// v scaled down so that its largest channel is at most `max` (pbrt-v4's maxcomponentvalue).
inline RGB clamp_max_component(const RGB& v, float max) {
    const float m = v.max_component();
    return m > max ? v * (max / m) : v;
}

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
    // From here on, keep each pixel's sample moments too (camera samples only: splats are
    // no samples of a pixel).
    void keep_moments() { moments_.assign(sum_.size(), SampleMoments{}); }
    bool keeps_moments() const { return !moments_.empty(); }
    // Camera samples and splats are clamped to this largest channel (FilmSettings).
    void set_max_sample_value(float max) { max_sample_ = max; }
    float max_sample_value() const { return max_sample_; }
    // One camera sample (clamped), with its moments when they are kept.
    void add_sample(std::size_t pixel, const RGB& value) {
        const RGB v = clamp_max_component(value, max_sample_);
        add(pixel, v);
        if (!moments_.empty()) moments_[pixel].add(v);
    }
    // Camera samples weighted by a pixel filter with negative lobes (pixel_filter.h): from here
    // on each pixel also sums its samples' weights, and mean() is the weighted mean, sum of
    // w v over sum of w (pbrt-v4's film: a flat region stays flat whatever the signs).
    void use_weights() { weight_.assign(sum_.size(), 0.0); }
    bool uses_weights() const { return !weight_.empty(); }
    // One camera sample of filter weight w (clamped before it is weighted, as pbrt-v4).
    void add_sample(std::size_t pixel, const RGB& value, float w) {
        const RGB v = clamp_max_component(value, max_sample_) * w;
        add(pixel, v);
        weight_[pixel] += double(w);
        if (!moments_.empty()) moments_[pixel].add(v);
    }
    // Adds to a pixel's weight sum alone (an estimate added with add() whose weights these are).
    void add_weight(std::size_t pixel, double w) { weight_[pixel] += w; }
    // A tile's pixel of `samples` samples whose moments are `m` (adaptive sampling).
    void add(std::size_t pixel, const RGB& value, uint32_t samples, const SampleMoments& m) {
        add(pixel, value, samples);
        if (!moments_.empty()) moments_[pixel].add(m);
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

    // The image as each pixel's mean (sum / samples, or sum / weights with use_weights();
    // black where there are none) ...
    Film mean() const;
    // ... or as the sums times one factor (splats: the paths traced are the samples of every
    // pixel at once).
    Film scaled(float factor) const;
    const std::vector<uint32_t>& samples() const { return count_; }
    // The variance AOV (Variance.R/G/B): each pixel's unbiased sample variance, 0 below two
    // samples. Needs keep_moments().
    AovLayer variance() const;
    std::size_t size() const { return sum_.size(); }

  private:
    int width_, height_;
    std::vector<RGB> sum_;
    std::vector<uint32_t> count_;
    std::vector<SampleMoments> moments_;
    std::vector<double> weight_;  // use_weights(): each pixel's sum of sample weights
    PixelOwners owners_;
    float max_sample_ = std::numeric_limits<float>::infinity();
};

}  // namespace foton
