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

const char* camera_type_name(CameraType t) {
    switch (t) {
        case CameraType::Perspective:
            return "perspective";
        case CameraType::Orthographic:
            return "orthographic";
        case CameraType::Equirectangular:
            return "equirectangular";
        case CameraType::Fisheye:
            return "fisheye";
    }
    return "?";
}

float Camera::pixel_angle() const {
    if (type == CameraType::Equirectangular) return 2.f * kPi / float(width);
    const float half_diagonal =
        0.5f * std::sqrt(float(width) * float(width) + float(height) * float(height));
    return 0.5f * fisheye_fov / half_diagonal;
}

void Camera::generate(float fx, float fy, Vec3& origin, Vec3& dir) const {
    if (panoramic()) {
        origin = eye;
        float sin_a, cos_a, sin_b, cos_b;
        if (type == CameraType::Equirectangular) {
            // Longitude from -pi (left edge) through 0 (the view direction) to pi; latitude
            // from pi/2 (top) to -pi/2.
            const float lon = kPi * (2.f * fx / float(width) - 1.f);
            const float lat = 0.5f * kPi * (1.f - 2.f * fy / float(height));
            sin_a = std::sin(lon);
            cos_a = std::cos(lon);
            sin_b = std::sin(lat);
            cos_b = std::cos(lat);
            dir = normalize(w * (cos_b * cos_a) + u * (cos_b * sin_a) + v * sin_b);
            return;
        }
        // Equidistant fisheye: the angle from w grows with the distance from the centre.
        const float x = fx - 0.5f * float(width), y = 0.5f * float(height) - fy;
        const float r = std::sqrt(x * x + y * y);
        const float theta = r * pixel_angle();
        if (r == 0.f) {
            dir = w;
            return;
        }
        sin_a = std::sin(theta);
        cos_a = std::cos(theta);
        dir = normalize(w * cos_a + (u * (x / r) + v * (y / r)) * sin_a);
        return;
    }
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

bool Camera::project_through(const Vec3& l, const Vec3& p, float& fx, float& fy,
                             float margin) const {
    if (lens_radius <= 0.f) return project(p, fx, fy, margin);
    const Vec3 dir = p - l;
    const float along = dot(dir, w);
    if (along <= 0.f) return false;
    return project(l + dir * (focal_distance / along), fx, fy, margin);
}

bool Camera::project(const Vec3& p, float& fx, float& fy, float margin) const {
    if (type != CameraType::Perspective) return false;
    const Vec3 q = p - eye;
    const float z = dot(q, w);
    if (z <= 0.f) return false;
    const float px = dot(q, u) * d / z, py = dot(q, v) * d / z;
    fx = px / pixel_size + 0.5f * float(width);
    fy = 0.5f * float(height) - py / pixel_size;
    const float m = margin;
    return fx >= float(x0) - m && fy >= float(y0) - m && fx < float(x0 + film_w()) + m &&
           fy < float(y0 + film_h()) + m;
}

float Camera::importance(float cos_theta, float dist) const {
    const float c3 = cos_theta * cos_theta * cos_theta;
    return d * d / (pixel_size * pixel_size * c3 * dist * dist);
}

float Camera::vertical_fov_degrees() const {
    return 2.f * std::atan(0.5f * float(height) * pixel_size / d) * 180.f / kPi;
}

std::array<float, 16> Camera::world_to_camera() const {
    // Row j is the j-th camera axis: M p = ((p - eye).u, .v, .w, 1) for a column vector p.
    const Vec3 axes[3] = {u, v, w};
    std::array<float, 16> m{};
    for (int j = 0; j < 3; ++j) {
        m[std::size_t(j * 4 + 0)] = axes[j].x;
        m[std::size_t(j * 4 + 1)] = axes[j].y;
        m[std::size_t(j * 4 + 2)] = axes[j].z;
        m[std::size_t(j * 4 + 3)] = -dot(eye, axes[j]);
    }
    m[15] = 1.f;
    return m;
}

std::array<float, 16> Camera::world_to_ndc() const {
    // pbrt-v4's NDCFromWorld: Translate(1/2, 1/2, 1/2) Scale(1/2, 1/2, 1/2) screenFromCamera
    // cameraFromWorld. screenFromCamera is pbrt's Perspective(fov, 1e-2, 1000), the field of
    // view spanning the image's shorter side (so screen x reaches +-aspect on a wide image),
    // or the identity for an orthographic camera (pbrt's Orthographic(0, 1)).
    double p[4][4] = {};
    if (type == CameraType::Perspective) {
        const double n = 1e-2, f = 1000.0;
        const double extent = double(pixel_size) * double(std::min(width, height));
        const double inv_tan = 2.0 * double(d) / extent;
        const double zz = f / (f - n);
        p[0][0] = 0.5 * inv_tan;
        p[0][2] = 0.5;
        p[1][1] = 0.5 * inv_tan;
        p[1][2] = 0.5;
        p[2][2] = 0.5 * zz + 0.5;
        p[2][3] = -0.5 * zz * n;
        p[3][2] = 1.0;
    } else {
        p[0][0] = p[1][1] = p[2][2] = 0.5;
        p[0][3] = p[1][3] = p[2][3] = 0.5;
        p[3][3] = 1.0;
    }
    const std::array<float, 16> c = world_to_camera();
    std::array<float, 16> m{};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            double sum = 0.0;
            for (int k = 0; k < 4; ++k) sum += p[i][k] * double(c[std::size_t(k * 4 + j)]);
            m[std::size_t(i * 4 + j)] = float(sum);
        }
    return m;
}

}  // namespace foton
