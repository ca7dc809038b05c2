#include "camera.h"

#include <cmath>

#include "engine/core/warp.h"

namespace foton {

void Camera::setup() {
    w = normalize(target - eye);
    // Right-handed: u = w x up points to the image's right when looking along w.
    u = normalize(cross(w, up));
    if (mirror) u = -u;
    v = mirror ? cross(w, u) : cross(u, w);
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
    origin = lens_point(lens);
    dir = normalize(focus - origin);
}

Vec3 Camera::lens_point(Point2 lens) const {
    if (lens_radius <= 0.f || type != CameraType::Perspective) return eye;
    const Point2 l = warp::concentric_disc(lens);
    return eye + u * (l.x * lens_radius) + v * (l.y * lens_radius);
}

bool Camera::project_through(const Vec3& l, const Vec3& p, float& fx, float& fy) const {
    if (lens_radius <= 0.f) return project(p, fx, fy);
    const Vec3 dir = p - l;
    const float along = dot(dir, w);
    if (along <= 0.f) return false;
    return project(l + dir * (focal_distance / along), fx, fy);
}

bool Camera::project(const Vec3& p, float& fx, float& fy) const {
    if (type != CameraType::Perspective) return false;
    const Vec3 q = p - eye;
    const float z = dot(q, w);
    if (z <= 0.f) return false;
    const float px = dot(q, u) * d / z, py = dot(q, v) * d / z;
    fx = px / pixel_size + 0.5f * float(width);
    fy = 0.5f * float(height) - py / pixel_size;
    return fx >= float(x0) && fy >= float(y0) && fx < float(x0 + film_w()) &&
           fy < float(y0 + film_h());
}

float Camera::importance(float cos_theta, float dist) const {
    const float c3 = cos_theta * cos_theta * cos_theta;
    return d * d / (pixel_size * pixel_size * c3 * dist * dist);
}

float Camera::vertical_fov_degrees() const {
    return 2.f * std::atan(0.5f * float(height) * pixel_size / d) * 180.f / kPi;
}

std::array<float, 16> Camera::world_to_camera() const {
    // Column j of the matrix is the j-th camera axis: p * M = ((p - eye).u, .v, .w, 1).
    const Vec3 axes[3] = {u, v, w};
    std::array<float, 16> m{};
    for (int j = 0; j < 3; ++j) {
        m[0 * 4 + j] = axes[j].x;
        m[1 * 4 + j] = axes[j].y;
        m[2 * 4 + j] = axes[j].z;
        m[3 * 4 + j] = -dot(eye, axes[j]);
    }
    m[15] = 1.f;
    return m;
}

std::array<float, 16> Camera::world_to_ndc() const {
    // Camera to NDC as a row-vector matrix P: perspective (x, y, z) -> (a x + z / 2,
    // -b y + z / 2, 1, z), which divides to (1/2 + a x / z, 1/2 - b y / z); orthographic
    // (1/2 + x / W, 1/2 - y / H), W and H the film's extent in scene units.
    const float wx = pixel_size * float(width), hy = pixel_size * float(height);
    std::array<float, 16> p{};
    if (type == CameraType::Perspective) {
        p = {d / wx, 0.f,     0.f, 0.f,  //
             0.f,    -d / hy, 0.f, 0.f,  //
             0.5f,   0.5f,    0.f, 1.f,  //
             0.f,    0.f,     1.f, 0.f};
    } else {
        p = {1.f / wx, 0.f,       0.f, 0.f,  //
             0.f,      -1.f / hy, 0.f, 0.f,  //
             0.f,      0.f,       1.f, 0.f,  //
             0.5f,     0.5f,      0.f, 1.f};
    }
    const std::array<float, 16> c = world_to_camera();
    std::array<float, 16> m{};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            for (int k = 0; k < 4; ++k) m[i * 4 + j] += c[i * 4 + k] * p[k * 4 + j];
    return m;
}

}  // namespace foton
