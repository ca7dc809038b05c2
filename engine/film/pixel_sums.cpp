#include "pixel_sums.h"

#include <algorithm>

namespace foton {

PixelSums::PixelSums(int width, int height)
    : width_(width),
      height_(height),
      sum_(std::size_t(width) * std::size_t(height), RGB{0.f}),
      count_(std::size_t(width) * std::size_t(height), 0) {}

std::size_t PixelSums::add_splats(const std::vector<std::vector<Splat>>& chunks, Share mine,
                                  const Cluster& cluster) {
    std::size_t count = 0;
    if (!cluster.distributed()) {
        for (uint64_t c = mine.begin; c < mine.end; ++c) {
            for (const Splat& s : chunks[c])
                sum_[s.pixel] += clamp_max_component(s.value, max_sample_);
            count += chunks[c].size();
        }
        return count;
    }
    std::size_t mine_count = 0;
    for (uint64_t c = mine.begin; c < mine.end; ++c) mine_count += chunks[c].size();
    Bytes packed;
    packed.reserve(mine_count * sizeof(Splat));
    for (uint64_t c = mine.begin; c < mine.end; ++c)
        pack(packed, chunks[c].data(), chunks[c].size());
    // Added straight from the messages, in rank order (= chunk order).
    const int me = cluster.rank();
    const std::vector<Bytes> parts =
        owners_.empty() ? cluster.gather(packed) : cluster.all_gather(packed);
    for (const Bytes& part : parts)
        for (Unpacker in(part); !in.done();) {
            const Splat s = in.value<Splat>();
            if (owners_.empty() || owners_[s.pixel] == me)
                sum_[s.pixel] += clamp_max_component(s.value, max_sample_), ++count;
        }
    return count;
}

void PixelSums::gather(const Cluster& cluster) {
    if (owners_.empty()) return;
    gather_to_root(cluster, owners_, sum_);
    gather_to_root(cluster, owners_, count_);
    if (!moments_.empty()) gather_to_root(cluster, owners_, moments_);
    if (!weight_.empty()) gather_to_root(cluster, owners_, weight_);
}

AovLayer PixelSums::variance() const {
    AovLayer l{"variance", aov_channels(kAovVariance), {}};
    l.values.assign(sum_.size() * 3, 0.f);
    for (std::size_t i = 0; i < moments_.size(); ++i) {
        const double n = double(count_[i]);
        if (n < 2.0) continue;
        for (std::size_t k = 0; k < 3; ++k) {
            const SampleMoments& m = moments_[i];
            const double v = (m.sum2[k] - m.sum[k] * m.sum[k] / n) / (n - 1.0);
            l.values[i * 3 + k] = float(std::max(v, 0.0));
        }
    }
    return l;
}

Film PixelSums::mean() const {
    Film f(width_, height_);
    for (std::size_t i = 0; i < sum_.size(); ++i)
        if (weight_.empty())
            f.pixels[i] = count_[i] ? sum_[i] * (1.f / float(count_[i])) : RGB{0.f};
        else
            f.pixels[i] = weight_[i] != 0.0 ? sum_[i] * float(1.0 / weight_[i]) : RGB{0.f};
    return f;
}

Film PixelSums::scaled(float factor) const {
    Film f(width_, height_);
    for (std::size_t i = 0; i < sum_.size(); ++i) f.pixels[i] = sum_[i] * factor;
    return f;
}

}  // namespace foton
