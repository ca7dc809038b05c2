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

#include "engine/core/distribution.h"
#include "engine/core/math.h"
#include "engine/core/rgb.h"
#include "texture.h"

namespace foton {

enum class EnvMapping : uint8_t { Constant, LatLong, EqualArea };
const char* env_mapping_name(EnvMapping m);

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

    EnvMapping mapping() const { return mapping_; }
    // Directions drawn uniformly over the sphere instead of by the map's density: the
    // baseline that importance sampling is measured against (<environment sampling="uniform">).
    void set_uniform_sampling(bool uniform) { uniform_ = uniform; }
    bool uniform_sampling() const { return uniform_; }
    const TextureImage& map() const { return map_; }
    const RGB& scale() const { return scale_; }

    // Radiance arriving along -wi, i.e. from world direction wi (unit).
    RGB Le(const Vec3& wi) const;
    // A direction wi towards the sky for u in [0, 1)^2, with its solid-angle pdf (0 when
    // the sample is void).
    Vec3 sample(Point2 u, float& pdf) const;
    float pdf(const Vec3& wi) const;
    // The integral of the radiance over the sphere, per channel (the map's texels by their
    // solid angles): the environment's power is pi r^2 times this.
    RGB integral() const { return integral_; }

    // The map's coordinates (u right, v down from the top row) of a world direction, and back.
    Point2 to_map(const Vec3& wi) const;
    Vec3 from_map(Point2 uv) const;

  private:
    EnvMapping mapping_ = EnvMapping::Constant;
    RGB scale_{1.f};
    TextureImage map_;
    Vec3 ex_{1, 0, 0}, ey_{0, 1, 0}, ez_{0, 0, 1};  // the map's frame in world directions
    Distribution2D dist_;
    RGB integral_{0.f};
    bool uniform_ = false;
};

// pbrt-v4's equal-area octahedral mapping between the square [0, 1)^2 and unit directions.
Vec3 equal_area_square_to_sphere(Point2 p);
Point2 equal_area_sphere_to_square(const Vec3& d);

}  // namespace foton
