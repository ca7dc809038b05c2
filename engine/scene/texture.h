#pragma once
// Textures on reflectances (and, read as floats, on roughness and displacement): constant, image
// (bilinear, repeating) and checkerboard, each evaluated at a surface's (u, v). Images are decoded
// once into linear float RGB and shared by every texture that names the same file
// (Scene::texture_images). Lookups are bilinear, or, for textures asking for it, trilinear
// between the levels of a MIP pyramid chosen by the surface point's footprint (the width of
// a pixel there, from the camera: surface_at); deterministic, the same for every thread
// count.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/core/math.h"
#include "engine/core/rgb.h"
#include "engine/core/sampler.h"

namespace foton {

// What an image holds beyond its edges, along one axis: itself again (the default), its edge
// texels (glTF's CLAMP_TO_EDGE, pbrt-v4's "clamp", MTL's -clamp on), itself mirrored every
// other period (glTF's MIRRORED_REPEAT), or black (pbrt-v4's "black").
enum class TextureWrap : uint8_t { Repeat, Clamp, Mirror, Black };
// "repeat", "clamp", "mirror" or "black"; false for anything else.
bool parse_texture_wrap(const std::string& name, TextureWrap& out);

// Texel index i (any real: uv far outside [0, 1] must not overflow) of an axis of n texels
// under `wrap`; `outside` is set when a Black axis leaves the image (the index is then an
// edge's).
int wrapped_texel_index(double i, int n, TextureWrap wrap, bool& outside);

struct TextureImage {
    std::string path;
    int width = 0, height = 0;
    std::vector<RGB> texels;  // row 0 is the image's top
    // The alpha channel, when the file has one that is not everywhere 1 (empty otherwise).
    std::vector<float> alpha;
    // Along u (s) and v (t): set by the texture that reads it (an image read under two wrap
    // modes is decoded twice), kept by its MIP levels.
    TextureWrap wrap_s = TextureWrap::Repeat, wrap_t = TextureWrap::Repeat;
    // Bilinear lookup at (u, v) under the wrap modes; v = 0 is the image's bottom (pbrt's and
    // glTF's convention after its flip, OBJ's).
    RGB bilinear(Point2 uv) const;
    float bilinear_alpha(Point2 uv) const;
    // The MIP pyramid: level k + 1 halves level k (box filter, odd sizes rounded up), down to
    // 1 x 1; empty until build_mip().
    std::vector<TextureImage> mip;
    void build_mip();
    // Trilinear lookup for a footprint `width` in (u, v) units (0: level 0, bilinear):
    // bilinear in the two levels whose texels bracket the width, blended by log2.
    RGB trilinear(Point2 uv, float width) const;
    // The texel nearest uv (pbrt-v4's point filter).
    RGB nearest(Point2 uv) const;
    // Elliptically weighted average (Heckbert 1989, as pbrt-v4's EWA): a Gaussian over the
    // ellipse of axes d0 and d1 (a pixel's step in x and y, in (u, v)) in the two levels
    // whose texels bracket its minor axis, the axes' ratio capped at max_anisotropy by
    // widening the minor one (texture_ewa.cpp).
    RGB ewa(Point2 uv, Point2 d0, Point2 d1, float max_anisotropy) const;
    // Level l of the pyramid (0: the image itself; past the last, the last).
    const TextureImage& level(int l) const {
        return l <= 0 || mip.empty() ? *this : mip[std::size_t(std::min(l, int(mip.size())) - 1)];
    }
    // Texel (x, y) under the wrap modes (row 0 at the top; black outside a Black axis).
    RGB texel(double x, double y) const;
};

// How an image texture is read: bilinearly (the default), the nearest texel, trilinearly
// between MIP levels by the footprint's width, or by an elliptical average over the
// footprint's ellipse (pbrt-v4's filters).
enum class TextureFilter : uint8_t { Bilinear, Point, Trilinear, Ewa };
const char* texture_filter_name(TextureFilter f);
// "bilinear", "point", "trilinear" or "ewa"; false for anything else.
bool parse_texture_filter(const std::string& name, TextureFilter& out);

enum class TextureKind : uint8_t {
    Constant,
    Image,
    Checkerboard,
    Mix,
    Product,
    DirectionMix,
    Noise,   // pbrt-v4's fbm, wrinkled and windy: Perlin noise at the point (noise.h)
    Bilerp,  // pbrt-v4's bilerp: operands v00, v01, v10, v11 bilinearly over (s, t), unwrapped
    Dots,    // pbrt-v4's dots: operands inside, outside; a dot of radius 0.35 in some unit cells
};

enum class NoiseKind : uint8_t { FBm, Wrinkled, Windy, Marble };

// How a texture finds its (s, t) at a surface point: the surface's uv through a UvMap, or the
// hit point in the texture's own space (pbrt-v4's spherical, cylindrical, planar mappings).
enum class TextureMapping : uint8_t { UV, Spherical, Cylindrical, Planar };

// Where a texture is read: the surface's uv and, for textures mapped by position or mixed by
// direction, the hit point and its (geometric) normal in world space.
struct TexPoint {
    Point2 uv;
    // The mesh's second uv set at the point (textures whose UvMap::set is 1); uv unless a
    // surface with one says otherwise. The footprint and steps below are the first set's.
    Point2 uv2;
    Vec3 p{0.f, 0.f, 0.f};
    Vec3 n{0.f, 0.f, 1.f};
    TexPoint(Point2 uv_) : uv(uv_), uv2(uv_) {}
    TexPoint(float u, float v) : uv{u, v}, uv2{u, v} {}
    TexPoint(Point2 uv_, const Vec3& p_, const Vec3& n_) : uv(uv_), uv2(uv_), p(p_), n(n_) {}
    // The width in (u, v) of the pixel's footprint at the point (0: unknown), for MIP-mapped
    // textures, and (for EWA) the uv change from one pixel to the next along the image's x
    // and y (both zero: unknown).
    float footprint = 0.f;
    Point2 duvdx{0.f, 0.f}, duvdy{0.f, 0.f};
    // The mesh's vertex colour interpolated at the point (white where it has none).
    RGB vertex_color{1.f};
    Point2 uv_of(uint8_t set) const { return set == 1 ? uv2 : uv; }
};

// A texture's affine map of the surface's uv: uv' = (su u + suv v + du, svu u + sv v + dv)
// (scale and offset from the XML, pbrt and MTL; glTF's KHR_texture_transform also rotates).
struct UvMap {
    float su = 1.f, sv = 1.f, du = 0.f, dv = 0.f, suv = 0.f, svu = 0.f;
    // The surface's uv set it reads: 0, or 1 for a mesh's second set (TexPoint::uv2).
    uint8_t set = 0;
    Point2 operator()(Point2 uv) const {
        return {su * uv.x + suv * uv.y + du, svu * uv.x + sv * uv.y + dv};
    }
};

struct Texture {
    TextureKind kind = TextureKind::Constant;
    RGB value{1.f};                                  // Constant; Checkerboard's first colour
    RGB other{0.f};                                  // Checkerboard's second colour
    uint32_t image = 0;                              // Image: into Scene::texture_images
    UvMap uv;                                        // where a surface uv reads it
    TextureFilter filter = TextureFilter::Bilinear;  // Image: how it is read
    float max_anisotropy = 8.f;                      // Image, EWA: the ellipse's axis ratio
    bool mip_mapped() const {
        return filter == TextureFilter::Trilinear || filter == TextureFilter::Ewa;
    }
    RGB scale{1.f};       // multiplies the result
    bool invert = false;  // max(0, 1 - scaled value) (pbrt's invert)
    // Mix (pbrt-v4's "mix"): (1 - t) tex1 + t tex2 with t = amount's float value, each operand
    // a texture of its own (a constant one for a value), read at the surface's uv.
    // Product (pbrt-v4's "scale" of a varying texture by a varying one): tex x scale's float.
    // DirectionMix: a tex1 + (1 - a) tex2 with a = |n . mix_dir| (pbrt-v4's directionmix).
    std::vector<Texture> operands;  // Mix: tex1, tex2, amount; Product: tex, scale; DirectionMix
    Vec3 mix_dir{0.f, 0.f, 1.f};    // DirectionMix: unit, world space
    // Noise: read at the point in the texture's space (to_texture), octaves of weight omega^k.
    NoiseKind noise = NoiseKind::FBm;
    float omega = 0.5f;
    int octaves = 8;
    // Marble (pbrt-v4's "marble", a colour): the point scaled by noise_scale, its y plus
    // variation x fbm through sin, read from a spline of veined greys.
    float noise_scale = 1.f, variation = 0.2f;
    // A mapping by position: world to the texture's space (the transform when the texture was
    // declared, inverted); Planar: s = du + q.plane_s, t = dv + q.plane_t (uv's du, dv).
    TextureMapping mapping = TextureMapping::UV;
    Affine to_texture;
    Vec3 plane_s{1.f, 0.f, 0.f}, plane_t{0.f, 1.f, 0.f};
    // The (s, t) this texture reads at `at` (texture_mapping.cpp).
    Point2 st(const TexPoint& at) const;
    // A Noise texture's value at q in its own space (a grey for the float kinds).
    RGB noise_value(const Vec3& q) const;
    // A Dots texture: whether (s, t) lies in a dot.
    bool in_dot(Point2 q) const;

    RGB eval(const std::vector<TextureImage>& images, const TexPoint& at) const;
    // An Image texture's image read at `at` through its filter (texture_filters.cpp).
    RGB image_value(const TextureImage& img, const TexPoint& at) const;
    // The mean over the texture's period (an image's texel mean, a checkerboard's two
    // colours' mean), as eval() scales and inverts: what an emitter's power is estimated by.
    RGB mean(const std::vector<TextureImage>& images) const;
    // As a float texture: the mean of the three channels (pbrt-v4's bilinear lookup of an RGB
    // image for a float texture; a grey image's value), or an image's alpha when it has one
    // (pbrt-v4 reads a four-channel image's alpha as its float value: alpha cut-outs).
    float eval_float(const std::vector<TextureImage>& images, const TexPoint& at) const;
};

// pbrt's parametrisation of a sphere at unit outward normal n: u = phi / 2 pi around z, v =
// 1 - theta / pi (1 at the top, +z).
Point2 sphere_uv(const Vec3& n);

// The sRGB transfer function's inverse: an encoded value in [0, 1] to linear.
float srgb_to_linear(float c);
// Whether a checkerboard is on its even squares at texture coordinates st (floor(s) + floor(t)
// even); defined for every float, however large.
bool checker_even(Point2 st);

// Decodes an EXR, HDR, PNG, JPEG, BMP or TGA file into linear RGB (8-bit files are sRGB
// encoded unless `linear`). Throws InputError naming the file.
TextureImage load_texture_image(const std::string& path, bool linear = false);

}  // namespace foton
