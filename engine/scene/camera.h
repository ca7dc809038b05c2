#pragma once
// Pinhole perspective and orthographic cameras of the first thesis: a view plane of
// width x height pixels of edge `pixel_size`, at distance d in front of the eye (perspective),
// with the orthonormal basis u (right), v (up), w (forward) built from eye, target and up.
#include "engine/core/math.h"

namespace foton {

enum class CameraType { Perspective, Orthographic };

struct Camera {
    CameraType type = CameraType::Perspective;
    Vec3 eye{0, 0, 0}, target{0, 0, -1}, up{0, 1, 0};
    float d = 1.f;         // eye to view-plane distance (perspective)
    float exposure = 1.f;  // scales the PNG preview
    float pixel_size = 0.001f;
    int width = 1, height = 1;

    // Derived basis (call setup() after changing the fields above).
    Vec3 u, v, w;
    void setup();

    // Ray through film position (fx, fy) in pixels, (0, 0) the top-left corner of the image.
    void generate(float fx, float fy, Vec3& origin, Vec3& dir) const;
    // Vertical field of view in degrees implied by d, pixel size and height.
    float vertical_fov_degrees() const;
};

}  // namespace foton
