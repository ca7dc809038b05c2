// How image textures are read beyond the bilinear lookup: the nearest texel, and the
// elliptically weighted average over a pixel's footprint (Heckbert 1989; pbrt-v4's EWA, our
// code): a Gaussian, exp(-2 r^2) - exp(-2) over the ellipse r < 1, in the MIP level whose
// texels are as wide as the ellipse's minor axis, blended with the next level by log2.
#include <algorithm>
#include <cmath>

#include "texture.h"

namespace foton {

namespace {

// The ellipse's average in one level: st in its texel coordinates (x right, y down, centres
// at half-integers), d0 and d1 its axes in texels.
RGB ewa_in_level(const TextureImage& img, Point2 uv, Point2 d0, Point2 d1) {
    double sd = double(uv.x) * img.width - 0.5, td = (1.0 - double(uv.y)) * img.height - 0.5;
    if (!std::isfinite(sd) || !std::isfinite(td)) return img.bilinear(uv);
    // Into the first period (of a repeating axis; a mirrored one repeats every two), so that
    // texel indices stay small; a clamped or black axis is constant a box's width beyond its
    // edges, so its coordinate is held there.
    auto near = [](double c, int n, TextureWrap w) {
        if (w == TextureWrap::Repeat) return c - std::floor(c / n) * n;
        if (w == TextureWrap::Mirror) return c - std::floor(c / (2.0 * n)) * 2.0 * n;
        return std::clamp(c, -128.0, n + 128.0);
    };
    sd = near(sd, img.width, img.wrap_s);
    td = near(td, img.height, img.wrap_t);
    const float s = float(sd), t = float(td);
    const float x0 = d0.x * float(img.width), y0 = -d0.y * float(img.height);
    const float x1 = d1.x * float(img.width), y1 = -d1.y * float(img.height);
    // The implicit ellipse A x^2 + B x y + C y^2 < 1, widened by a texel so that it covers at
    // least one texel centre (pbrt-v4's + 1).
    float a = y0 * y0 + y1 * y1 + 1.f, b = -2.f * (x0 * y0 + x1 * y1), c = x0 * x0 + x1 * x1 + 1.f;
    const float inv_f = 1.f / (a * c - 0.25f * b * b);
    a *= inv_f;
    b *= inv_f;
    c *= inv_f;
    const float det = 4.f * a * c - b * b;
    if (!(det > 0.f) || !std::isfinite(det)) return img.bilinear(uv);
    // Its bounding box, at most 64 texels a side (the anisotropy cap keeps it far smaller).
    const float half_s = std::min(2.f * std::sqrt(det * c) / det, 32.f);
    const float half_t = std::min(2.f * std::sqrt(det * a) / det, 32.f);
    const int sa = int(std::ceil(s - half_s)), sb = int(std::floor(s + half_s));
    const int ta = int(std::ceil(t - half_t)), tb = int(std::floor(t + half_t));
    const float edge = std::exp(-2.f);
    RGB sum{0.f};
    float weight = 0.f;
    for (int it = ta; it <= tb; ++it) {
        const float tt = float(it) - t;
        for (int is = sa; is <= sb; ++is) {
            const float ss = float(is) - s;
            const float r2 = a * ss * ss + b * ss * tt + c * tt * tt;
            if (r2 >= 1.f) continue;
            const float w = std::exp(-2.f * r2) - edge;
            sum += img.texel(is, it) * w;
            weight += w;
        }
    }
    return weight > 0.f ? sum * (1.f / weight) : img.bilinear(uv);
}

}  // namespace

const char* texture_filter_name(TextureFilter f) {
    switch (f) {
        case TextureFilter::Bilinear:
            return "bilinear";
        case TextureFilter::Point:
            return "point";
        case TextureFilter::Trilinear:
            return "trilinear";
        case TextureFilter::Ewa:
            return "ewa";
    }
    return "?";
}

bool parse_texture_filter(const std::string& name, TextureFilter& out) {
    for (TextureFilter f : {TextureFilter::Bilinear, TextureFilter::Point, TextureFilter::Trilinear,
                            TextureFilter::Ewa})
        if (name == texture_filter_name(f)) {
            out = f;
            return true;
        }
    return false;
}

RGB TextureImage::texel(double x, double y) const {
    bool outside = false;
    const int i = wrapped_texel_index(x, width, wrap_s, outside);
    const int j = wrapped_texel_index(y, height, wrap_t, outside);
    return outside ? RGB{0.f} : texels[std::size_t(j) * std::size_t(width) + std::size_t(i)];
}

RGB TextureImage::nearest(Point2 uv) const {
    const double x = std::floor(double(uv.x) * width),
                 y = std::floor((1.0 - double(uv.y)) * height);
    if (!std::isfinite(x) || !std::isfinite(y)) return texels[0];
    return texel(x, y);
}

RGB TextureImage::ewa(Point2 uv, Point2 d0, Point2 d1, float max_anisotropy) const {
    float l0 = std::sqrt(d0.x * d0.x + d0.y * d0.y), l1 = std::sqrt(d1.x * d1.x + d1.y * d1.y);
    if (l0 < l1) {
        std::swap(d0, d1);
        std::swap(l0, l1);
    }
    if (!(l1 > 0.f) || !std::isfinite(l0)) return bilinear(uv);
    // Too eccentric: widen the minor axis (blurrier, but a bounded number of texels).
    if (l1 * max_anisotropy < l0) {
        const float k = l0 / (l1 * max_anisotropy);
        d1 = {d1.x * k, d1.y * k};
        l1 *= k;
    }
    const float texels_across = l1 * float(std::max(width, height));
    const float lod = std::max(0.f, std::log2(std::max(texels_across, 1e-8f)));
    const int l = int(lod);
    if (mip.empty() || l >= int(mip.size())) return ewa_in_level(level(l), uv, d0, d1);
    const float f = lod - float(l);
    return ewa_in_level(level(l), uv, d0, d1) * (1.f - f) +
           ewa_in_level(level(l + 1), uv, d0, d1) * f;
}

RGB Texture::image_value(const TextureImage& img, const TexPoint& at) const {
    const Point2 q = st(at);
    switch (filter) {
        case TextureFilter::Bilinear:
            return img.bilinear(q);
        case TextureFilter::Point:
            return img.nearest(q);
        case TextureFilter::Ewa: {
            // The pixel's uv steps through the texture's map (its linear part), when the hit
            // has them and the texture reads the surface's uv.
            const bool steps =
                at.duvdx.x != 0.f || at.duvdx.y != 0.f || at.duvdy.x != 0.f || at.duvdy.y != 0.f;
            if (steps && mapping == TextureMapping::UV) {
                auto map = [&](Point2 d) {
                    return Point2{uv.su * d.x + uv.suv * d.y, uv.svu * d.x + uv.sv * d.y};
                };
                return img.ewa(q, map(at.duvdx), map(at.duvdy), max_anisotropy);
            }
            [[fallthrough]];
        }
        case TextureFilter::Trilinear:
            // The footprint is in the surface's uv; the texture's map scales it (its largest
            // stretch).
            return img.trilinear(
                q, at.footprint * std::max({std::fabs(uv.su), std::fabs(uv.sv), std::fabs(uv.suv),
                                            std::fabs(uv.svu)}));
    }
    return img.bilinear(q);
}

}  // namespace foton
