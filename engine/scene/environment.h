#pragma once
// The environment: light arriving from infinitely far away in every direction, either a
// constant sky or an image over the sphere of directions. It is an emitter like any other
// (light_set.h): next event estimation samples it with a piecewise-constant density over its
// texels proportional to their luminance (times the mapping's Jacobian), BSDF-sampled rays
// that leave the scene find it, and light paths and photons start on a disc facing the
// scene from outside its bounding sphere.
//
// Two mappings of the image: lat-long (equirectangular: columns are longitude, rows the
// angle from the map's up axis, row 0 at the top) and pbrt-v4's equal-area octahedral square
// (Clarberg 2008), which pbrt-v4's "infinite" lights use. Lookups take the nearest texel, as
// pbrt-v4 does: the radiance is then exactly the piecewise-constant function the sampling
// density follows, so a lit map is sampled with no mismatch between the two.
#include <cstdint>
#include <vector>

#include "engine/core/distribution.h"
#include "engine/core/math.h"
#include "engine/core/rgb.h"
#include "engine/core/windowed_distribution.h"
#include "texture.h"

namespace foton {

enum class EnvMapping : uint8_t { Constant, LatLong, EqualArea, Portal };
const char* env_mapping_name(EnvMapping m);

// One source of light at infinity: a constant sky, an image in one of the mappings, or
// pbrt-v4's portal light, an equal-area image seen only through a rectangle (a window):
// resampled at load into the portal's rectified map, where the directions from any point
// through the rectangle form an axis-aligned window (alpha = atan(x / z), beta = atan(y / z)
// in the portal's frame), so that next event estimation samples just those directions.
struct EnvLayer {
    EnvMapping mapping = EnvMapping::Constant;
    RGB scale{1.f};
    TextureImage map;                            // the image (a portal's rectified one)
    Vec3 ex{1, 0, 0}, ey{0, 1, 0}, ez{0, 0, 1};  // its frame (a portal's: edges 03, 01, normal)
    Distribution2D dist;               // lat-long and equal-area maps' density over texels
    WindowedDistribution window_dist;  // a portal's, sampled within a window
    Vec3 corners[4];                   // a portal's rectangle
    RGB integral{0.f};                 // radiance over the sphere of directions
    float pick = 1.f;                  // its share of the environment's samples

    // The map's coordinates of a world direction, and back (not for portals).
    Point2 to_map(const Vec3& wi) const;
    Vec3 from_map(Point2 uv) const;
    // A portal's rectified coordinates of wi (false: not out through its plane) with
    // d omega / d(u, v), and back.
    bool to_portal(const Vec3& wi, Point2& uv, float* dw_duv = nullptr) const;
    Vec3 from_portal(Point2 uv, float& dw_duv) const;
    // The window of directions from p through the portal (false: p is not behind it).
    bool window_from(const Vec3& p, Window2& w) const;
    RGB texel(Point2 uv) const;  // the nearest texel times the scale
    // A portal: the ray from `from` along d crosses its rectangle.
    bool crosses_portal(const Vec3& from, const Vec3& d) const;
};

// The frame an environment map is oriented by (its up axis ez and longitude 0 ex), and the
// check of its texels (finite; the brightest times the scale a representable radiance).
void env_map_frame(const Vec3& up, const Vec3& front, Vec3& ex, Vec3& ey, Vec3& ez);
void check_env_texels(const TextureImage& map, const RGB& scale);

class Environment {
  public:
    // A constant sky of the given radiance.
    static Environment constant(const RGB& radiance);
    // An image map times `scale`. `up` and `front` (world directions, need not be unit)
    // orient it: the map's up axis (lat-long row 0, the equal-area square's +z) and the
    // direction of longitude 0 (the first column's edge; the square's +x). Throws
    // InputError naming the image when it is not square for EqualArea or entirely black.
    static Environment image(TextureImage map, EnvMapping mapping, const RGB& scale, const Vec3& up,
                             const Vec3& front);
    // pbrt-v4's portal light: an equal-area `map` (oriented as image() orients it) whose light
    // arrives only through the rectangle of corners c[0..3] (in order round it); its rectified
    // map has the equal-area map's resolution. Throws InputError when c is no rectangle.
    static Environment portal(const TextureImage& map, const RGB& scale, const Vec3& up,
                              const Vec3& front, const Vec3 c[4]);
    // Whether c[0..3] go round a rectangle (what portal() asks of its corners).
    static bool is_rectangle(const Vec3 c[4]);
    // Adds another environment's light: several infinite lights are their sum, each sampled in
    // proportion to its power.
    void add(const Environment& other);

    const std::vector<EnvLayer>& layers() const { return layers_; }
    bool has_portal() const;
    // Directions drawn uniformly over the sphere instead of by the map's density: the
    // baseline that importance sampling is measured against (<environment sampling="uniform">).
    void set_uniform_sampling(bool uniform) { uniform_ = uniform; }
    bool uniform_sampling() const { return uniform_; }

    // Radiance arriving at p from world direction wi (unit): through a portal only when the
    // ray from p along wi passes its rectangle.
    RGB Le(const Vec3& p, const Vec3& wi) const;
    // A direction wi towards the sky seen from p for u in [0, 1)^2, with its solid-angle pdf
    // (0 when the sample is void), and that pdf for a given direction.
    Vec3 sample(const Vec3& p, Point2 u, float& pdf) const;
    float pdf(const Vec3& p, const Vec3& wi) const;
    // Light paths leaving the environment: a direction towards the sky over all of it (a
    // portal's whole map), its pdf, and the radiance of the ray that enters the scene from
    // `from` (outside it) along -wi: through a portal only if it crosses the rectangle.
    Vec3 sample_emission(Point2 u, float& pdf) const;
    float pdf_emission(const Vec3& wi) const;
    RGB Le_emitted(const Vec3& from, const Vec3& wi) const;
    // The integral of the radiance over the sphere, per channel (the map's texels by their
    // solid angles): the environment's power is pi r^2 times this.
    RGB integral() const { return integral_; }

  private:
    void finish();  // the layers' shares and the integral
    // The layer u.x picks, u.x rescaled to reuse within it.
    const EnvLayer& pick(Point2& u) const;
    std::vector<EnvLayer> layers_;
    RGB integral_{0.f};
    bool uniform_ = false;
};

// pbrt-v4's equal-area octahedral mapping between the square [0, 1)^2 and unit directions.
Vec3 equal_area_square_to_sphere(Point2 p);
Point2 equal_area_sphere_to_square(const Vec3& d);

}  // namespace foton
