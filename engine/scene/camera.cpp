#include "camera.h"

#include <cmath>

namespace foton {

void Camera::setup() {
    w = normalize(target - eye);
    // Right-handed: u = w x up points to the image's right when looking along w.
    u = normalize(cross(w, up));
    v = cross(u, w);
}

void Camera::generate(float fx, float fy, Vec3& origin, Vec3& dir) const {
    const float px = pixel_size * (fx - 0.5f * float(width));
    const float py = pixel_size * (0.5f * float(height) - fy);
    if (type == CameraType::Perspective) {
        origin = eye;
        dir = normalize(u * px + v * py + w * d);
    } else {
        origin = eye + u * px + v * py;
        dir = w;
    }
}

float Camera::vertical_fov_degrees() const {
    return 2.f * std::atan(0.5f * float(height) * pixel_size / d) * 180.f / kPi;
}

}  // namespace foton
