// Structural similarity (film/ssim.h) against the values its definition gives by hand.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "engine/film/ssim.h"

using namespace foton;

namespace {

Film gray(int w, int h, float v) {
    Film f(w, h);
    for (RGB& p : f.pixels) p = RGB{v};
    return f;
}

// A smooth ramp with some texture, so that windows have structure.
Film pattern(int w, int h) {
    Film f(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            f.at(x, y) =
                RGB{0.2f + 0.5f * float(x) / float(w) + 0.1f * std::sin(0.7f * float(x + 2 * y))};
    return f;
}

Film noisy(const Film& f, float sigma, unsigned seed) {
    Film g = f;
    std::mt19937 rng(seed);
    std::normal_distribution<float> n(0.f, sigma);
    for (RGB& p : g.pixels) p = RGB{std::max(0.f, p.r + n(rng))};
    return g;
}

}  // namespace

TEST_CASE("ssim: equal images give 1, constant ones the luminance term", "[metrics][fast]") {
    const Film a = pattern(40, 30);
    CHECK(ssim(a, a) == Approx(1.0).margin(1e-12));
    // Two flat images: no variance, so SSIM is (2xy + C1) / (x^2 + y^2 + C1) of the display
    // values x = 0.25^(1/2.2), y = 0.75^(1/2.2) (a gray's luminance is its value).
    const double g = 1.0 / double(2.2f);  // the display gamma, as the float it is
    const double x = std::pow(0.25, g), y = std::pow(0.75, g), c1 = 1e-4;
    CHECK(ssim(gray(20, 20, 0.25f), gray(20, 20, 0.75f)) ==
          Approx((2 * x * y + c1) / (x * x + y * y + c1)).epsilon(1e-9));
    // The exposure scales before the clamp: 2 x 0.25 against 2 x 0.75 = 1.5, clamped to 1.
    const double x2 = std::pow(0.5, g);
    CHECK(ssim(gray(20, 20, 0.25f), gray(20, 20, 0.75f), nullptr, 2.f) ==
          Approx((2 * x2 + c1) / (x2 * x2 + 1 + c1)).epsilon(1e-9));
}

TEST_CASE("ssim: symmetric, lower with more noise, blind to masked-out pixels", "[metrics][fast]") {
    const Film a = pattern(48, 40);
    const Film b1 = noisy(a, 0.02f, 1), b2 = noisy(a, 0.1f, 2);
    const double s1 = ssim(a, b1), s2 = ssim(a, b2);
    CHECK(ssim(b1, a) == Approx(s1).epsilon(1e-12));
    CHECK(s1 < 1.0);
    CHECK(s2 < s1);
    CHECK(s2 > 0.0);
    // A difference confined to the left half is invisible when only the right half's window
    // centres (6 or more pixels from it) count.
    Film c = a;
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < 20; ++x) c.at(x, y) = RGB{0.f};
    std::vector<uint8_t> right(a.pixels.size(), 0);
    for (int y = 0; y < a.height; ++y)
        for (int x = 26; x < a.width; ++x) right[std::size_t(y) * a.width + x] = 1;
    CHECK(ssim(a, c) < 0.9);
    CHECK(ssim(a, c, &right) == Approx(1.0).margin(1e-12));
    // NaN pixels count as black rather than poisoning the mean.
    Film d = a;
    d.at(3, 3) = RGB{std::nanf("")};
    CHECK(std::isfinite(ssim(a, d)));
    // Images smaller than the window shrink it; one pixel compares the luminance term alone.
    CHECK(ssim(gray(1, 1, 0.5f), gray(1, 1, 0.5f)) == Approx(1.0));
    const std::vector<uint8_t> none(a.pixels.size(), 0);
    CHECK(std::isnan(ssim(a, a, &none)));
}
