#pragma once
// Pinhole perspective and orthographic cameras of the first thesis: a view plane of
// width x height pixels of edge `pixel_size`, at distance d in front of the eye (perspective),
// with the orthonormal basis u (right), v (up), w (forward) built from eye, target and up.
// And its panoramic ones (4): equirectangular (longitude across the image, 360 degrees,
// latitude down it, 180, the view direction at the centre) and a full-frame equidistant
// fisheye (the angle from the view direction proportional to the distance from the image's
// centre, `fisheye_fov` across its diagonal). Panoramic cameras have no view plane: nothing
// projects onto them (the light tracer and the bidirectional integrators refuse them).
#include <algorithm>
#include <array>

#include "engine/core/math.h"
#include "engine/core/sampler.h"

namespace foton {

enum class CameraType { Perspective, Orthographic, Equirectangular, Fisheye };

// A perspective view a model file carries (glTF's first camera), in world space: what
// `foton render model.gltf` looks through.
struct ModelView {
    Vec3 eye, target, up;
    float vertical_fov_degrees = 40.f;
    float aspect = 0.f;  // width / height the file asks for (glTF's aspectRatio); 0: none
    // An orthographic view (glTF's): the view plane's half height in scene units (ymag),
    // the aspect from xmag / ymag; the field of view is not used.
    bool orthographic = false;
    float half_height = 0.f;
};
const char* camera_type_name(CameraType t);

struct Camera {
    CameraType type = CameraType::Perspective;
    Vec3 eye{0, 0, 0}, target{0, 0, -1}, up{0, 1, 0};
    float d = 1.f;         // eye to view-plane distance (perspective)
    float exposure = 1.f;  // scales the PNG preview
    float pixel_size = 0.001f;
    int width = 1, height = 1;  // the whole image
    // The film's pixels within the image (a crop window): film pixel (x, y) is image pixel
    // (x0 + x, y0 + y). film_width 0 means the whole image. Rays and projections are in
    // image positions, so a crop's rays are the full render's, bit for bit.
    int x0 = 0, y0 = 0, film_width = 0, film_height = 0;
    int film_w() const { return film_width > 0 ? film_width : width; }
    int film_h() const { return film_height > 0 ? film_height : height; }
    void crop(int x, int y, int w, int h) {
        x0 = x;
        y0 = y;
        film_width = w;
        film_height = h;
    }
    // Thin lens (distributed ray tracing): aperture radius and the distance of the plane in
    // focus along the view direction. lens_radius = 0 is the pinhole.
    float lens_radius = 0.f;
    float focal_distance = 1.f;
    // The fisheye's field of view across the image diagonal, in radians (up to 2 pi).
    float fisheye_fov = kPi;
    bool panoramic() const {
        return type == CameraType::Equirectangular || type == CameraType::Fisheye;
    }
    // The angle one pixel spans at the centre of a panoramic image.
    float pixel_angle() const;

    // The image's x axis reversed (u = up x w): pbrt's left-handed camera space.
    bool mirror = false;

    // Derived basis (call setup() after changing the fields above).
    Vec3 u, v, w;
    void setup();

    // Ray through image position (fx, fy) in pixels, (0, 0) the top-left corner of the image.
    void generate(float fx, float fy, Vec3& origin, Vec3& dir) const;
    // The same through the thin lens, `lens` uniform in the unit square.
    void generate(float fx, float fy, Point2 lens, Vec3& origin, Vec3& dir) const;
    // Image position (pixels) of a world point seen by the pinhole; false when it is behind
    // the eye or off the film (outside the crop window widened by `margin` pixels: a pixel
    // filter wider than a pixel reaches the film from there, PixelFilter::margin).
    bool project(const Vec3& p, float& fx, float& fy, float margin = 0.f) const;
    // The same for the ray from lens point `l` (on the thin lens) through p: the image position
    // of the point where it crosses the plane in focus (for the pinhole, l = eye, project()).
    bool project_through(const Vec3& l, const Vec3& p, float& fx, float& fy,
                         float margin = 0.f) const;
    // A point on the lens for `u` uniform in the unit square (the eye for a pinhole).
    Vec3 lens_point(Point2 u) const;
    // Importance of the pinhole for a 1-pixel box towards a point at distance `dist` with
    // cos_theta between the view axis and the ray: the pixel's measurement is the mean
    // radiance over its area on the view plane, which in terms of the surface seen is
    // d^2 / (pixel_size^2 cos^3 dist^2) per unit of (cos at the surface dA). A wider pixel
    // filter spreads it over the pixels it reaches (FilmSettings::spread), weights summing
    // to its normalised integral.
    float importance(float cos_theta, float dist) const;
    // Edge of a pixel's footprint at `distance` along a camera ray (scene units).
    float footprint(float distance) const {
        if (panoramic()) return distance * pixel_angle();
        return type == CameraType::Perspective ? distance * pixel_size / d : pixel_size;
    }
    // Vertical field of view in degrees implied by d, pixel size and height.
    float vertical_fov_degrees() const;
    // OpenEXR's worldToCamera and worldToNDC attributes as pbrt-v4 writes them: row-major 4 x 4
    // matrices acting on column vectors (the translation in the last column), camera space
    // x right, y up, z along the view, and pbrt's NDC (y up; x in +-aspect around 1/2 on a
    // wide image, see world_to_ndc). tests/test_exr_metadata.cpp holds them to pbrt-v4's EXR.
    std::array<float, 16> world_to_camera() const;
    std::array<float, 16> world_to_ndc() const;
};

}  // namespace foton
