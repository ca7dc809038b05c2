// MIP-mapped textures (filter="trilinear" and "ewa", as pbrt-v4's): the pyramid's levels are
// block means, the lookup blends the levels a footprint brackets, and a fine checkerboard far
// away renders as its mean instead of aliasing; EWA averages over the footprint's ellipse, so
// stripes running away from the camera keep their contrast where trilinear blurs them.
#include <bit>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <fstream>

#include "engine/core/rng.h"
#include "engine/scene/texture.h"
#include "engine/scene/xml_loader.h"
#include "test_util.h"

using namespace foton;

TEST_CASE("mip: levels are block means down to one texel, odd sizes included", "[mip][fast]") {
    TextureImage img;
    img.width = 5;
    img.height = 3;
    for (int i = 0; i < 15; ++i) img.texels.push_back(RGB{float(i)});
    img.build_mip();
    REQUIRE(img.mip.size() == 3);
    CHECK(img.mip[0].width == 3);
    CHECK(img.mip[0].height == 2);
    CHECK(img.mip[2].width == 1);
    CHECK(img.mip[2].height == 1);
    // Level 1's first texel: texels 0, 1, 5, 6; its last column holds the lone column 4.
    CHECK(img.mip[0].texels[0].r == Approx((0 + 1 + 5 + 6) / 4.f));
    CHECK(img.mip[0].texels[2].r == Approx((4 + 9) / 2.f));
    CHECK(img.mip[0].texels[3].r == Approx((10 + 11) / 2.f));
    // A 4 x 4 image: the last level is the mean; a footprint as wide as the image reads it,
    // no footprint reads level 0.
    TextureImage sq;
    sq.width = sq.height = 4;
    float sum = 0.f;
    for (int i = 0; i < 16; ++i) {
        sq.texels.push_back(RGB{float(i * i % 7)});
        sum += float(i * i % 7);
    }
    sq.build_mip();
    REQUIRE(sq.mip.size() == 2);
    CHECK(sq.mip[1].texels[0].r == Approx(sum / 16.f));
    for (const Point2 uv : {Point2{0.1f, 0.2f}, Point2{0.7f, 0.55f}}) {
        CHECK(sq.trilinear(uv, 1.f).r == Approx(sum / 16.f));
        CHECK(sq.trilinear(uv, 0.f).r == sq.bilinear(uv).r);
        // Halfway (in log2) between levels 0 and 1: the mean of their bilinear lookups.
        CHECK(sq.trilinear(uv, std::sqrt(2.f) / 4.f).r ==
              Approx(0.5f * (sq.bilinear(uv).r + sq.mip[0].bilinear(uv).r)));
    }
}

namespace {

// An n x n grey PFM file of texel values value(x, y).
template <class Value>
void write_grey_pfm(const std::string& path, int n, Value&& value) {
    std::string s = "PF\n" + std::to_string(n) + " " + std::to_string(n) + "\n-1.0\n";
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            for (int c = 0; c < 3; ++c) {
                const float v = value(x, y);
                char b[4];
                std::memcpy(b, &v, 4);
                s.append(b, 4);
            }
    std::ofstream(path, std::ios::binary) << s;
}

// A 256 x 256 checkerboard of single texels, 0 and 1.
void write_checks(const std::string& path) {
    write_grey_pfm(path, 256, [](int x, int y) { return float((x + y) % 2); });
}

}  // namespace

TEST_CASE("mip: a fine checkerboard far away renders as its mean, not as aliasing",
          "[mip][render]") {
    test::TempDir dir;
    write_checks(dir.file("checks.pfm"));
    // The board (8 texels to a pixel) in ambient light only, by the Whitted tracer: each pixel
    // is its one sample's texture value, with no Monte Carlo noise on top.
    auto render_with = [&](const char* filter) {
        const std::string xml = std::string(R"(<scene>
  <ambient r="1" g="1" b="1" intensity="1"/>
  <objects><quad><corner x="-1" y="-1" z="0"/><edge1 x="2" y="0" z="0"/><edge2 x="0" y="2" z="0"/>
    <material type="matte" c_ambient="1" c_diffuse="1"><base_color r="1" g="1" b="1"/>
      <texture type="image" src="checks.pfm" encoding="linear" filter=")") +
                                filter + R"("/></material></quad></objects>
  <film width="32" height="32" size="0.0625"/>
  <renderer type="raytracer"/>
  <camera type="orthographic"><eye x="0" y="0" z="5"/><target x="0" y="0" z="0"/>
    <up x="0" y="1" z="0"/></camera>
</scene>)";
        TestScene s(parse_scene(xml, "board.xml", dir.path().string()));
        const Film f = render_test(s, 1, 0, 3).film;
        double mean = 0.0, sq = 0.0;
        for (const RGB& p : f.pixels) {
            mean += p.g / double(f.pixels.size());
            sq += double(p.g) * p.g / double(f.pixels.size());
        }
        return std::pair{mean, std::sqrt(std::max(0.0, sq - mean * mean))};
    };
    const auto [mean_mip, sd_mip] = render_with("trilinear");
    const auto [mean_bi, sd_bi] = render_with("bilinear");
    INFO("trilinear " << mean_mip << " +- " << sd_mip << ", bilinear " << mean_bi << " +- "
                      << sd_bi);
    // Ambient light times the checks: their mean is 0.5.
    CHECK(mean_mip == Approx(0.5).epsilon(0.05));
    CHECK(sd_mip < 0.1 * sd_bi);
    CHECK(sd_bi > 0.1);
    // EWA over the same (round) footprint averages as well.
    const auto [mean_ewa, sd_ewa] = render_with("ewa");
    INFO("ewa " << mean_ewa << " +- " << sd_ewa);
    CHECK(mean_ewa == Approx(0.5).epsilon(0.05));
    CHECK(sd_ewa < 0.1 * sd_bi);
}

TEST_CASE("ewa: the elliptical average keeps detail along the footprint's short axis",
          "[mip][ewa][fast]") {
    // Vertical stripes, one texel each, 0 and 1 alternating along u, 64 x 64.
    TextureImage img;
    img.width = img.height = 64;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) img.texels.push_back(RGB{float(x % 2)});
    img.build_mip();
    const float texel = 1.f / 64.f;
    // At a bright column's centre: an ellipse long along v (the stripes' direction) and half a
    // texel wide keeps the stripe; the same width along u averages the stripes away, as does
    // the trilinear lookup by the long axis.
    const Point2 bright{(1.f + 0.5f) * texel, 0.5f};
    const RGB along = img.ewa(bright, {0.f, 8.f * texel}, {0.5f * texel, 0.f}, 16.f);
    const RGB across = img.ewa(bright, {8.f * texel, 0.f}, {0.f, 0.5f * texel}, 16.f);
    const RGB tri = img.trilinear(bright, 8.f * texel);
    INFO("along " << along.g << ", across " << across.g << ", trilinear " << tri.g);
    CHECK(along.g > 0.8f);
    CHECK(across.g == Approx(0.5f).margin(0.1f));
    CHECK(tri.g == Approx(0.5f).margin(0.05f));
    // The anisotropy cap widens the short axis: 1:64 capped at 4 blurs the stripes away.
    CHECK(img.ewa(bright, {0.f, 32.f * texel}, {0.5f * texel, 0.f}, 4.f).g ==
          Approx(0.5f).margin(0.1f));
    // A constant image stays constant; a zero-width ellipse is the bilinear lookup.
    TextureImage flat;
    flat.width = flat.height = 8;
    flat.texels.assign(64, RGB{0.25f, 0.5f, 0.75f});
    flat.build_mip();
    const RGB c = flat.ewa({0.3f, 0.7f}, {0.2f, 0.1f}, {-0.05f, 0.1f}, 8.f);
    CHECK(c.r == Approx(0.25f));
    CHECK(c.b == Approx(0.75f));
    CHECK(img.ewa(bright, {0.f, 0.f}, {0.f, 0.f}, 8.f).g == img.bilinear(bright).g);
    // Far outside [0, 1] the image repeats.
    CHECK(img.ewa({bright.x + 1000.f, 0.5f - 2000.f}, {0.f, 8.f * texel}, {0.5f * texel, 0.f}, 16.f)
              .g == Approx(along.g).margin(1e-3f));
    TextureFilter f;
    CHECK(parse_texture_filter("ewa", f));
    CHECK(f == TextureFilter::Ewa);
    CHECK_FALSE(parse_texture_filter("gaussian", f));
}

TEST_CASE("ewa: stripes running away from the camera stay sharp where trilinear blurs them",
          "[mip][ewa][render]") {
    test::TempDir dir;
    // Stripes along v, 2 texels wide, 64 x 64 (0 and 1), on a floor running away from a low
    // perspective camera: across the image a stripe spans pixels, along it they shrink.
    write_grey_pfm(dir.file("stripes.pfm"), 64, [](int x, int) { return float((x / 2) % 2); });
    auto render_with = [&](const char* filter) {
        const std::string xml = std::string(R"(<scene>
  <ambient r="1" g="1" b="1" intensity="1"/>
  <objects><quad><corner x="-1" y="0" z="0"/><edge1 x="2" y="0" z="0"/><edge2 x="0" y="0" z="-40"/>
    <material type="matte" c_ambient="1" c_diffuse="1"><base_color r="1" g="1" b="1"/>
      <texture type="image" src="stripes.pfm" encoding="linear" filter=")") +
                                filter + R"("/></material></quad></objects>
  <film width="64" height="32" size="0.02"/>
  <renderer type="raytracer"/>
  <camera><eye x="0" y="0.3" z="1"/><target x="0" y="0" z="-3"/><up x="0" y="1" z="0"/></camera>
</scene>)";
        TestScene s(parse_scene(xml, "floor.xml", dir.path().string()));
        const Film f = render_test(s, 1, 0, 3).film;
        // Contrast across the middle rows of the floor: the standard deviation along x.
        double sd = 0.0;
        int rows = 0;
        for (int y = 18; y < 26; ++y, ++rows) {
            double m = 0.0, q = 0.0;
            for (int x = 16; x < 48; ++x) {
                const double v = f.at(x, y).g;
                m += v / 32.0;
                q += v * v / 32.0;
            }
            sd += std::sqrt(std::max(0.0, q - m * m));
        }
        return sd / rows;
    };
    const double ewa = render_with("ewa"), tri = render_with("trilinear");
    const double bi = render_with("bilinear");
    INFO("contrast: ewa " << ewa << ", trilinear " << tri << ", bilinear " << bi);
    CHECK(ewa > 2.0 * tri);
    CHECK(ewa > 0.1);
}
