#include "camera.h"

#include <cmath>

#include "engine/core/warp.h"

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

void Camera::generate(float fx, float fy, Point2 lens, Vec3& origin, Vec3& dir) const {
    generate(fx, fy, origin, dir);
    if (lens_radius <= 0.f || type != CameraType::Perspective) return;
    // Every ray through the lens meets the pinhole ray on the plane in focus.
    const Vec3 focus = origin + dir * (focal_distance / dot(dir, w));
    const Point2 l = warp::concentric_disc(lens);
    origin = eye + u * (l.x * lens_radius) + v * (l.y * lens_radius);
    dir = normalize(focus - origin);
}

bool Camera::project(const Vec3& p, float& fx, float& fy) const {
    if (type != CameraType::Perspective) return false;
    const Vec3 q = p - eye;
    const float z = dot(q, w);
    if (z <= 0.f) return false;
    const float px = dot(q, u) * d / z, py = dot(q, v) * d / z;
    fx = px / pixel_size + 0.5f * float(width);
    fy = 0.5f * float(height) - py / pixel_size;
    return fx >= 0.f && fy >= 0.f && fx < float(width) && fy < float(height);
}

float Camera::importance(float cos_theta, float dist) const {
    const float c3 = cos_theta * cos_theta * cos_theta;
    return d * d / (pixel_size * pixel_size * c3 * dist * dist);
}

float Camera::vertical_fov_degrees() const {
    return 2.f * std::atan(0.5f * float(height) * pixel_size / d) * 180.f / kPi;
}

}  // namespace foton
