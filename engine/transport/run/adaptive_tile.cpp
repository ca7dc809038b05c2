#include "adaptive_tile.h"

#include <algorithm>
#include <cmath>

#include "engine/film/pixel_sums.h"

namespace foton {

namespace {

// Luminance statistics of one pixel's samples, for the stopping rule.
struct PixelMoments {
    double sum = 0.0, sum2 = 0.0;
    uint32_t n = 0;
    void add(float y) {
        sum += y;
        sum2 += double(y) * y;
        ++n;
    }
    double mean() const { return n ? sum / n : 0.0; }
    // Unbiased sample variance of one sample (the thesis' s^2 times N).
    double variance() const {
        if (n < 2) return 0.0;
        return std::max(0.0, (sum2 - sum * sum / n) / (n - 1));
    }
    // Standard error of the mean relative to the mean (absolute below a small floor).
    double relative_error() const {
        return std::sqrt(variance() / std::max<uint32_t>(n, 1)) / std::max(mean(), 1e-3);
    }
};

}  // namespace

void adaptive_tile(const Scene& scene, const AdaptiveSettings& ad, SamplerKind sampler,
                   uint64_t seed, const CameraIntegrator& integrator, const Tile& t,
                   IntegratorWorkspace& ws, RenderStats& st, std::vector<SampleJob>& jobs,
                   std::vector<RGB>& out, TileSums& sums) {
    const int tw = t.x1 - t.x0;
    const std::size_t n_pixels = std::size_t(t.pixels());
    const uint32_t n_parts = ws.part_count;
    std::vector<PixelMoments> mom(n_pixels);
    sums.sum.assign(n_pixels, RGB{0.f});
    sums.moments.assign(n_pixels, SampleMoments{});
    sums.parts.assign(n_pixels * n_parts, RGB{0.f});
    sums.weight.assign(scene.film.filter.negative_lobes() ? n_pixels : 0, 0.0);
    std::vector<float> weights;
    std::vector<uint32_t> want(n_pixels, ad.pilot);
    std::vector<uint32_t> taken(n_pixels, 0);
    auto local = [&](const SampleJob& j) { return std::size_t(j.y - t.y0) * tw + (j.x - t.x0); };
    auto run_round = [&](uint32_t round) {
        jobs.clear();
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const std::size_t l = std::size_t(y - t.y0) * tw + (x - t.x0);
                const uint64_t pixel = scene.film.pixel_id(uint32_t(x), uint32_t(y));
                for (uint32_t s = 0; s < want[l]; ++s)
                    jobs.push_back({uint32_t(x), uint32_t(y), s, want[l], round,
                                    (pixel << 24) + taken[l] + s});
                taken[l] += want[l];
            }
        if (jobs.empty()) return false;
        ws.parts.assign(jobs.size() * n_parts, RGB{0.f});
        integrator.trace(jobs, ws, out, st);
        // A filter with negative lobes weighs each sample (pixel_sums.h's weighted mean).
        const bool weighted = camera_sample_weights(scene, sampler, jobs, seed, weights);
        st.samples += jobs.size();
        for (std::size_t i = 0; i < jobs.size(); ++i) {
            const std::size_t l = local(jobs[i]);
            const float w = weighted ? weights[i] : 1.f;
            const RGB v = clamp_max_component(out[i], scene.film.max_sample_value) * w;
            mom[l].add(v.luminance());
            sums.sum[l] += v;
            sums.moments[l].add(v);
            if (weighted) sums.weight[l] += double(w);
            for (uint32_t c = 0; c < n_parts; ++c)
                sums.parts[l * n_parts + c] += ws.parts[i * n_parts + c] * w;
        }
        return true;
    };
    run_round(0);
    if (ad.unbiased) {
        // Samples needed for the target error, from the pilot's variance; then a fresh
        // estimate from only those.
        for (std::size_t l = 0; l < mom.size(); ++l) {
            const double target = ad.threshold * std::max(mom[l].mean(), 1e-3);
            const double n = std::ceil(mom[l].variance() / (target * target));
            want[l] = uint32_t(std::clamp(n, 1.0, double(ad.max_spp - ad.pilot)));
            if (ad.max_spp == ad.pilot) want[l] = 0;
            if (want[l] > 0) {
                mom[l] = {};
                sums.sum[l] = RGB{0.f};
                sums.moments[l] = {};
                for (uint32_t c = 0; c < n_parts; ++c) sums.parts[l * n_parts + c] = RGB{0.f};
            }
        }
        run_round(1);
    } else {
        for (uint32_t round = 1;; ++round) {
            for (std::size_t l = 0; l < mom.size(); ++l) {
                const bool noisy = mom[l].relative_error() > ad.threshold;
                want[l] = noisy ? std::min(mom[l].n, ad.max_spp - mom[l].n) : 0;
            }
            if (!run_round(round)) break;
        }
    }
    sums.count.resize(mom.size());
    for (std::size_t l = 0; l < mom.size(); ++l) sums.count[l] = mom[l].n;
}

}  // namespace foton
