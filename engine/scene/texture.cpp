#include "texture.h"

#include <stb/stb_image.h>
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "engine/core/error.h"
#include "engine/core/input_file.h"
#include "engine/core/params.h"
#include "engine/film/image_io.h"
#include "engine/film/pfm_reader.h"
#include "noise.h"

namespace foton {

bool parse_texture_wrap(const std::string& name, TextureWrap& out) {
    static const EnumTable<TextureWrap> names{{{"repeat", TextureWrap::Repeat},
                                               {"clamp", TextureWrap::Clamp},
                                               {"mirror", TextureWrap::Mirror},
                                               {"black", TextureWrap::Black}}};
    return names.parse(name, out);
}

int wrapped_texel_index(double i, int n, TextureWrap wrap, bool& outside) {
    if (!std::isfinite(i)) return 0;
    const double dn = double(n);
    switch (wrap) {
        case TextureWrap::Repeat:
            return std::clamp(int(i - std::floor(i / dn) * dn), 0, n - 1);
        case TextureWrap::Mirror: {
            const double m = i - std::floor(i / (2.0 * dn)) * 2.0 * dn;  // [0, 2n)
            return std::clamp(int(m < dn ? m : 2.0 * dn - 1.0 - m), 0, n - 1);
        }
        case TextureWrap::Black:
            if (i < 0.0 || i >= dn) outside = true;
            [[fallthrough]];
        case TextureWrap::Clamp:
            return int(std::clamp(i, 0.0, dn - 1.0));
    }
    return 0;
}

bool checker_even(Point2 st) {
    // The parity of floor(s) + floor(t) in double arithmetic: a float beyond 2^63 (a scale of
    // 1e30) must not be converted to an integer, which is undefined behaviour. Every float
    // above 2^24 is even, so the pattern there is uniform, as the float grid is.
    auto parity = [](float v) {
        const double f = std::floor(double(v));
        return f - 2.0 * std::floor(0.5 * f);  // 0 or 1; NaN for a non-finite v
    };
    return parity(st.x) + parity(st.y) != 1.0;
}

float srgb_to_linear(float c) {
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

namespace {

// The four texels around uv and their bilinear weights (texel centres at half-integers; v
// runs up the image), under the image's wrap modes: a tap outside a Black axis weighs 0.
struct TextureTaps {
    std::size_t i[4];  // (x0, y0), (x1, y0), (x0, y1), (x1, y1)
    float w[4];        // the bilinear weights
};

TextureTaps texture_taps(Point2 uv, const TextureImage& img) {
    const double x = double(uv.x) * img.width - 0.5, y = (1.0 - double(uv.y)) * img.height - 0.5;
    const double fx = std::floor(x), fy = std::floor(y);
    if (!std::isfinite(fx) || !std::isfinite(fy)) return {{0, 0, 0, 0}, {0.f, 0.f, 0.f, 0.f}};
    const float tx = float(x - fx), ty = float(y - fy);
    bool out[4] = {false, false, false, false};  // x0, x1, y0, y1 outside a Black axis
    const int xa = wrapped_texel_index(fx, img.width, img.wrap_s, out[0]);
    const int xb = wrapped_texel_index(fx + 1.0, img.width, img.wrap_s, out[1]);
    const int ya = wrapped_texel_index(fy, img.height, img.wrap_t, out[2]);
    const int yb = wrapped_texel_index(fy + 1.0, img.height, img.wrap_t, out[3]);
    auto at = [&](int i, int j) {
        return std::size_t(j) * std::size_t(img.width) + std::size_t(i);
    };
    auto in = [&](int i, int j) { return out[i] || out[2 + j] ? 0.f : 1.f; };
    return {{at(xa, ya), at(xb, ya), at(xa, yb), at(xb, yb)},
            {(1.f - tx) * (1.f - ty) * in(0, 0), tx * (1.f - ty) * in(1, 0),
             (1.f - tx) * ty * in(0, 1), tx * ty * in(1, 1)}};
}

}  // namespace

RGB TextureImage::bilinear(Point2 uv) const {
    const TextureTaps b = texture_taps(uv, *this);
    return texels[b.i[0]] * b.w[0] + texels[b.i[1]] * b.w[1] + texels[b.i[2]] * b.w[2] +
           texels[b.i[3]] * b.w[3];
}

void TextureImage::build_mip() {
    mip.clear();
    const TextureImage* prev = this;
    while (prev->width > 1 || prev->height > 1) {
        TextureImage next;
        next.path = path;
        next.wrap_s = wrap_s;
        next.wrap_t = wrap_t;
        next.width = std::max(1, (prev->width + 1) / 2);
        next.height = std::max(1, (prev->height + 1) / 2);
        next.texels.resize(std::size_t(next.width) * std::size_t(next.height));
        for (int y = 0; y < next.height; ++y)
            for (int x = 0; x < next.width; ++x) {
                // The 2 x 2 block under the texel (a lone last row or column: its own).
                RGB sum{0.f};
                int n = 0;
                for (int dy = 0; dy < 2; ++dy)
                    for (int dx = 0; dx < 2; ++dx) {
                        const int sx = 2 * x + dx, sy = 2 * y + dy;
                        if (sx >= prev->width || sy >= prev->height) continue;
                        sum += prev->texels[std::size_t(sy) * std::size_t(prev->width) +
                                            std::size_t(sx)];
                        ++n;
                    }
                next.texels[std::size_t(y) * std::size_t(next.width) + std::size_t(x)] =
                    sum * (1.f / float(n));
            }
        mip.push_back(std::move(next));
        prev = &mip.back();
    }
}

RGB TextureImage::trilinear(Point2 uv, float width) const {
    // The level whose texel is as wide as the footprint: log2 of the footprint in level-0
    // texels.
    const float texels_across = width * float(std::max(this->width, height));
    if (mip.empty() || !(texels_across > 1.f)) return bilinear(uv);
    const float level = std::min(std::log2(texels_across), float(mip.size()));
    const int l0 = int(level);
    const float t = level - float(l0);
    auto at = [&](int l) { return l == 0 ? bilinear(uv) : mip[std::size_t(l - 1)].bilinear(uv); };
    if (l0 >= int(mip.size())) return at(int(mip.size()));
    return at(l0) * (1.f - t) + at(l0 + 1) * t;
}

float TextureImage::bilinear_alpha(Point2 uv) const {
    if (alpha.empty()) return 1.f;
    const TextureTaps b = texture_taps(uv, *this);
    return alpha[b.i[0]] * b.w[0] + alpha[b.i[1]] * b.w[1] + alpha[b.i[2]] * b.w[2] +
           alpha[b.i[3]] * b.w[3];
}

float Texture::eval_float(const std::vector<TextureImage>& images, const TexPoint& at) const {
    float v;
    if (kind == TextureKind::Product) {
        v = operands[0].eval_float(images, at) * operands[1].eval_float(images, at);
    } else if (kind == TextureKind::Mix || kind == TextureKind::DirectionMix) {
        // The operands as floats (an RGBA image's alpha, as for any float texture).
        const float t = kind == TextureKind::Mix ? operands[2].eval_float(images, at)
                                                 : 1.f - std::fabs(dot(at.n, mix_dir));
        v = operands[0].eval_float(images, at) * (1.f - t) + operands[1].eval_float(images, at) * t;
    } else if (kind == TextureKind::Image && !images[image].alpha.empty()) {
        v = images[image].bilinear_alpha(st(at));
    } else {
        const RGB c = eval(images, at);
        return (c.r + c.g + c.b) * (1.f / 3.f);
    }
    v *= scale.r;
    return invert ? std::max(0.f, 1.f - v) : v;
}

bool Texture::in_dot(Point2 q) const {
    // The unit cell around the nearest integer point holds a dot where the noise at its
    // centre is positive; the dot's centre is shifted within the cell by two more draws.
    const float s_cell = std::floor(q.x + 0.5f), t_cell = std::floor(q.y + 0.5f);
    if (!(perlin_noise({s_cell + 0.5f, t_cell + 0.5f, 0.5f}) > 0.f)) return false;
    constexpr float kRadius = 0.35f, kMaxShift = 0.5f - kRadius;
    const float sc = s_cell + kMaxShift * perlin_noise({s_cell + 1.5f, t_cell + 2.8f, 0.5f});
    const float tc = t_cell + kMaxShift * perlin_noise({s_cell + 4.5f, t_cell + 9.8f, 0.5f});
    const float ds = q.x - sc, dt = q.y - tc;
    return ds * ds + dt * dt < kRadius * kRadius;
}

namespace {

// pbrt-v4's marble: t = (1 + sin(y + variation fbm)) / 2 read from a cubic Bezier spline
// through veined greys, its segment chosen by t (its colour table; the same construction).
RGB marble_color(const Vec3& q, float variation, float omega, int octaves) {
    static constexpr float kVeins[9][3] = {{.58f, .58f, .6f}, {.58f, .58f, .6f}, {.58f, .58f, .6f},
                                           {.5f, .5f, .5f},   {.6f, .59f, .58f}, {.58f, .58f, .6f},
                                           {.58f, .58f, .6f}, {.2f, .2f, .33f},  {.58f, .58f, .6f}};
    constexpr int kSegments = 9 - 3;
    float t = 0.5f + 0.5f * std::sin(q.y + variation * fbm(q, omega, octaves));
    const int first = std::clamp(int(std::floor(t * kSegments)), 0, kSegments - 1);
    t = t * kSegments - float(first);
    // The Bezier of control points kVeins[first .. first + 3] at t.
    const float s = 1.f - t;
    const float w[4] = {s * s * s, 3.f * s * s * t, 3.f * s * t * t, t * t * t};
    RGB c{0.f};
    for (int k = 0; k < 4; ++k)
        c += RGB{kVeins[first + k][0], kVeins[first + k][1], kVeins[first + k][2]} * w[k];
    return c * 1.5f;
}

}  // namespace

RGB Texture::noise_value(const Vec3& q) const {
    switch (noise) {
        case NoiseKind::FBm:
            return RGB{fbm(q, omega, octaves)};
        case NoiseKind::Wrinkled:
            return RGB{turbulence(q, omega, octaves)};
        case NoiseKind::Windy:
            // pbrt-v4's waves: a slow fbm's strength times a finer one's height.
            return RGB{std::fabs(fbm(q * 0.1f, 0.5f, 3)) * fbm(q, 0.5f, 6)};
        case NoiseKind::Marble:
            return marble_color(q * noise_scale, variation, omega, octaves);
    }
    return RGB{0.f};
}

RGB Texture::eval(const std::vector<TextureImage>& images, const TexPoint& at) const {
    RGB c = value;
    switch (kind) {
        case TextureKind::Mix: {
            const float t = operands[2].eval_float(images, at);
            c = operands[0].eval(images, at) * (1.f - t) + operands[1].eval(images, at) * t;
            break;
        }
        case TextureKind::DirectionMix: {
            const float a = std::fabs(dot(at.n, mix_dir));
            c = operands[0].eval(images, at) * a + operands[1].eval(images, at) * (1.f - a);
            break;
        }
        case TextureKind::Product:
            c = operands[0].eval(images, at) * operands[1].eval_float(images, at);
            break;
        case TextureKind::Noise:
            c = noise_value(to_texture.point(at.p));
            break;
        case TextureKind::Bilerp: {
            const Point2 q = st(at);
            c = operands[0].eval(images, at) * ((1.f - q.x) * (1.f - q.y)) +
                operands[1].eval(images, at) * ((1.f - q.x) * q.y) +
                operands[2].eval(images, at) * (q.x * (1.f - q.y)) +
                operands[3].eval(images, at) * (q.x * q.y);
            break;
        }
        case TextureKind::Dots:
            c = operands[in_dot(st(at)) ? 0 : 1].eval(images, at);
            break;
        case TextureKind::Constant:
            break;
        case TextureKind::Image:
            c = image_value(images[image], at);
            break;
        case TextureKind::Checkerboard:
            c = checker_even(st(at)) ? value : other;
            break;
    }
    c *= scale;
    if (invert) c = {std::max(0.f, 1.f - c.r), std::max(0.f, 1.f - c.g), std::max(0.f, 1.f - c.b)};
    return c;
}

RGB Texture::mean(const std::vector<TextureImage>& images) const {
    RGB c = value;
    if (kind == TextureKind::Image) {
        RGB sum{0.f};
        for (const RGB& t : images[image].texels) sum += t;
        c = sum * (1.f / float(images[image].texels.size()));
    } else if (kind == TextureKind::Checkerboard) {
        c = (value + other) * 0.5f;
    } else if (kind == TextureKind::DirectionMix) {
        c = (operands[0].mean(images) + operands[1].mean(images)) * 0.5f;
    } else if (kind == TextureKind::Bilerp) {
        c = (operands[0].mean(images) + operands[1].mean(images) + operands[2].mean(images) +
             operands[3].mean(images)) *
            0.25f;
    } else if (kind == TextureKind::Dots) {
        // A dot covers pi 0.35^2 of about half the cells.
        const float f = 0.5f * kPi * 0.35f * 0.35f;
        c = operands[0].mean(images) * f + operands[1].mean(images) * (1.f - f);
    } else if (kind == TextureKind::Noise) {
        // Over a fixed scatter of points (the noise has no period to average over).
        RGB sum{0.f};
        for (int i = 0; i < 256; ++i)
            sum += noise_value({float(i) * 0.377f, float(i) * 0.713f, float(i) * 0.131f});
        c = sum * (1.f / 256.f);
    } else if (kind == TextureKind::Mix) {
        // The operands' means mixed by the amount's (exact when the amount is constant or
        // independent of the operands).
        const RGB a = operands[2].mean(images);
        const float t = (a.r + a.g + a.b) * (1.f / 3.f);
        c = operands[0].mean(images) * (1.f - t) + operands[1].mean(images) * t;
    } else if (kind == TextureKind::Product) {
        // Exact when the two are independent (different images or periods).
        const RGB s = operands[1].mean(images);
        c = operands[0].mean(images) * ((s.r + s.g + s.b) * (1.f / 3.f));
    }
    c *= scale;
    if (invert) c = {std::max(0.f, 1.f - c.r), std::max(0.f, 1.f - c.g), std::max(0.f, 1.f - c.b)};
    return c;
}

Point2 sphere_uv(const Vec3& n) {
    float phi = std::atan2(n.y, n.x);
    if (phi < 0.f) phi += 2.f * kPi;
    return {phi / (2.f * kPi), 1.f - std::acos(std::clamp(n.z, -1.f, 1.f)) / kPi};
}

TextureImage load_texture_image(const std::string& path, bool linear) {
    const std::string problem = input_file_problem(path, kMaxMeshFileBytes);
    if (!problem.empty()) throw InputError(path, 0, "cannot read texture: " + problem);
    TextureImage img;
    img.path = path;
    const std::string ext = lower_extension(path);
    if (ext == ".exr" || ext == ".pfm") {
        const Film f = ext == ".exr" ? read_exr(path) : read_pfm(path);
        img.width = f.width;
        img.height = f.height;
        img.texels = f.pixels;
    } else {
        int w = 0, h = 0, c = 0;
        if (!stbi_info(path.c_str(), &w, &h, &c))
            throw InputError(
                path, 0,
                std::string("not a readable image (EXR, PFM, HDR, PNG, JPEG, BMP, TGA): ") +
                    stbi_failure_reason());
        check_claimed_size(path, w, h, 2048);
        img.width = w;
        img.height = h;
        img.texels.resize(std::size_t(w) * std::size_t(h));
        // A file with alpha (grey + alpha, RGBA) keeps it, linear as PNG defines it.
        const int n = c == 2 || c == 4 ? 4 : 3;
        auto store = [&](auto* data, float unit, bool encoded) {
            if (!data)
                throw InputError(path, 0,
                                 std::string("cannot decode image: ") + stbi_failure_reason());
            if (w != img.width || h != img.height) {
                stbi_image_free(data);
                throw InputError(path, 0, "the image changed while it was read");
            }
            if (n == 4) img.alpha.resize(img.texels.size());
            for (std::size_t i = 0; i < img.texels.size(); ++i) {
                float v[3];
                for (int k = 0; k < 3; ++k) {
                    v[k] = float(data[std::size_t(n) * i + std::size_t(k)]) / unit;
                    if (encoded && !linear) v[k] = srgb_to_linear(v[k]);
                }
                img.texels[i] = {v[0], v[1], v[2]};
                if (n == 4) img.alpha[i] = float(data[4 * i + 3]) / unit;
            }
            stbi_image_free(data);
            // An alpha channel that is everywhere 1 cuts nothing: dropped.
            bool opaque = true;
            for (float a : img.alpha) opaque = opaque && a >= 1.f;
            if (opaque) img.alpha.clear();
        };
        // Radiance HDR files are linear; 8- and 16-bit files are sRGB encoded.
        if (stbi_is_hdr(path.c_str()))
            store(stbi_loadf(path.c_str(), &w, &h, &c, n), 1.f, false);
        else if (stbi_is_16_bit(path.c_str()))
            store(stbi_load_16(path.c_str(), &w, &h, &c, n), 65535.f, true);
        else
            store(stbi_load(path.c_str(), &w, &h, &c, n), 255.f, true);
    }
    for (const RGB& t : img.texels)
        if (!std::isfinite(t.r) || !std::isfinite(t.g) || !std::isfinite(t.b) || t.r < 0.f ||
            t.g < 0.f || t.b < 0.f)
            throw InputError(path, 0, "texture holds negative, NaN or infinite values");
    if (img.texels.empty()) throw InputError(path, 0, "empty texture");
    return img;
}

}  // namespace foton
