#pragma once
// Convergence checks the integrator tests share: channel means within a relative tolerance,
// and the worst block of a downsampled image.
#include <catch2/catch.hpp>
#include <cmath>

#include "engine/core/rgb.h"
#include "engine/film/film.h"
#include "engine/film/metrics.h"

namespace foton::test {

inline void check_means(const RGB& got, const RGB& ref, double tolerance) {
    INFO("means " << got.r << " " << got.g << " " << got.b << ", reference " << ref.r << " "
                  << ref.g << " " << ref.b);
    CHECK(got.r == Approx(ref.r).epsilon(tolerance));
    CHECK(got.g == Approx(ref.g).epsilon(tolerance));
    CHECK(got.b == Approx(ref.b).epsilon(tolerance));
}

// The largest relative luminance error of block x block blocks of img against ref.
inline void check_blocks(const Film& img, const Film& ref, int block, double tolerance) {
    const Film a = downsample(img, block), b = downsample(ref, block);
    double worst = 0;
    std::size_t where = 0;
    for (std::size_t i = 0; i < b.pixels.size(); ++i) {
        const double e = std::fabs(a.pixels[i].luminance() / b.pixels[i].luminance() - 1.0);
        if (e > worst) worst = e, where = i;
    }
    INFO("worst " << block << "x" << block << " block " << worst << " at (" << where % b.width
                  << ", " << where / b.width << ")");
    CHECK(worst < tolerance);
}

}  // namespace foton::test
