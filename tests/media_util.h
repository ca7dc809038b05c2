#pragma once
// What the media tests share: channel means of whole and masked images, and the foggy box.
#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/core/rng.h"
#include "engine/film/metrics.h"
#include "engine/scene/medium.h"
#include "engine/scene/xml_loader.h"
#include "test_util.h"

namespace foton::test {

// Counter-based uniforms for one test: number k of draw sequence i of stream `stream`.
struct Draws {
    uint64_t seed, stream, i = 0, k = 0;
    float operator()() { return rng::uniform(seed, stream, i, k++); }
};

// exp(-integral of sigma_t) per channel along o + t d over [0, t_end) through a grid medium,
// by a 20,000-step midpoint rule.
inline RGB exact_transmittance(const Medium& m, const Vec3& o, const Vec3& d, float t_end) {
    const int steps = 20000;
    double tau[3] = {0, 0, 0};
    for (int i = 0; i < steps; ++i) {
        const MediumPoint c = m.at(o + d * ((i + 0.5f) * t_end / steps));
        const RGB st = c.sigma_a + c.sigma_s;
        tau[0] += st.r * (t_end / steps);
        tau[1] += st.g * (t_end / steps);
        tau[2] += st.b * (t_end / steps);
    }
    return {float(std::exp(-tau[0])), float(std::exp(-tau[1])), float(std::exp(-tau[2]))};
}

// The image's channel means (film/metrics.h's comparison of the image with itself).
inline RGB image_mean(const Film& f) {
    return compare_images(f, f).mean_a;
}

// 1 where `ref` is below its brightest 3 %: the small light of the foggy box covers a seventh
// of a pixel at 24 x 24 yet, at radiance 600, carries 40 % of the image's mean, which a handful
// of camera samples per pixel cannot average.
inline std::vector<uint8_t> below_brightest(const Film& ref) {
    std::vector<float> lum;
    for (const RGB& p : ref.pixels) lum.push_back(p.r + p.g + p.b);
    std::vector<float> sorted = lum;
    std::sort(sorted.begin(), sorted.end());
    const float cut = sorted[sorted.size() * 97 / 100];
    std::vector<uint8_t> mask(lum.size());
    for (std::size_t i = 0; i < lum.size(); ++i) mask[i] = lum[i] < cut ? 1 : 0;
    return mask;
}

// The mean of f over the pixels below_brightest(ref).
inline RGB masked_mean(const Film& f, const Film& ref) {
    const std::vector<uint8_t> mask = below_brightest(ref);
    return compare_images(f, ref, &mask).mean_a;
}

inline TestScene fog(int size) {
    TestScene s = load_scene(source_path("scenes/cornell-fog.xml"));
    s.set_resolution(size, size);
    return s;
}

}  // namespace foton::test
