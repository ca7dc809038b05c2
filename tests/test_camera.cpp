#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "engine/scene/camera.h"

using namespace foton;

namespace {
Camera make(CameraType type) {
    Camera c;
    c.type = type;
    c.eye = {278, 277.5f, -800};
    c.target = {278, 277.5f, 0};
    c.up = {0, 1, 0};
    c.width = 512;
    c.height = 256;
    c.d = 2.f;
    c.pixel_size = 0.004f;
    c.setup();
    return c;
}
}  // namespace

TEST_CASE("perspective camera rays for known pixels", "[camera][fast]") {
    const Camera c = make(CameraType::Perspective);
    Vec3 o, d;
    // Image centre: straight down the view axis.
    c.generate(256.f, 128.f, o, d);
    CHECK(o == c.eye);
    CHECK(d.x == Approx(0.f).margin(1e-6));
    CHECK(d.y == Approx(0.f).margin(1e-6));
    CHECK(d.z == Approx(1.f));
    // Top-left corner: view plane at distance d, half extents 256 * s and 128 * s. Looking
    // along +z with up +y, the image's right is -x (the Cornell box's red wall is on the left).
    c.generate(0.f, 0.f, o, d);
    const Vec3 expect = normalize(Vec3{256 * 0.004f, 128 * 0.004f, 2.f});
    CHECK(d.x == Approx(expect.x));
    CHECK(d.y == Approx(expect.y));
    CHECK(d.z == Approx(expect.z));
    // Bottom-right corner mirrors it.
    c.generate(512.f, 256.f, o, d);
    CHECK(d.x == Approx(-expect.x));
    CHECK(d.y == Approx(-expect.y));
    CHECK(c.vertical_fov_degrees() == Approx(2.0 * std::atan(128 * 0.004 / 2.0) * 180.0 / M_PI));
}

TEST_CASE("orthographic camera rays are parallel and offset on the view plane", "[camera][fast]") {
    const Camera c = make(CameraType::Orthographic);
    Vec3 o, d;
    c.generate(256.f, 128.f, o, d);
    CHECK(o.x == Approx(278.f));
    CHECK(o.y == Approx(277.5f));
    CHECK(d.z == Approx(1.f));
    c.generate(0.f, 0.f, o, d);
    CHECK(d.z == Approx(1.f));
    CHECK(o.x == Approx(278.f + 256 * 0.004f));  // image left is +x
    CHECK(o.y == Approx(277.5f + 128 * 0.004f));
}

TEST_CASE("panoramic cameras: equirectangular and fisheye directions are analytic",
          "[camera][fast]") {
    // The view axis is +z, the image's right -x (u), up +y (v); see the perspective case.
    Camera e = make(CameraType::Equirectangular);
    Vec3 o, d;
    auto near = [](const Vec3& a, const Vec3& b) { return length(a - b) < 1e-5f; };
    e.generate(256.f, 128.f, o, d);
    CHECK(o == e.eye);
    CHECK(near(d, e.w));
    e.generate(384.f, 128.f, o, d);  // a quarter turn to the right: longitude pi/2
    CHECK(near(d, e.u));
    e.generate(0.f, 128.f, o, d);  // the left edge looks backwards
    CHECK(near(d, -e.w));
    e.generate(256.f, 0.f, o, d);  // the top row looks straight up
    CHECK(near(d, e.v));
    e.generate(128.f, 64.f, o, d);  // longitude -pi/2, latitude pi/4
    CHECK(near(d, normalize(e.v - e.u)));
    CHECK(e.footprint(10.f) == Approx(10.f * 2.f * kPi / 512.f));
    // Equidistant fisheye of 180 degrees across the diagonal: the angle from the view axis
    // grows linearly with the distance from the centre, 90 degrees at the corners.
    Camera f = make(CameraType::Fisheye);
    f.fisheye_fov = kPi;
    f.generate(256.f, 128.f, o, d);
    CHECK(near(d, f.w));
    f.generate(0.f, 0.f, o, d);
    const float half_diagonal = std::sqrt(256.f * 256.f + 128.f * 128.f);
    CHECK(dot(d, f.w) == Approx(0.f).margin(1e-6));
    CHECK(near(d, normalize(f.u * -256.f + f.v * 128.f)));
    f.generate(256.f + 0.5f * half_diagonal, 128.f, o, d);  // halfway out: 45 degrees
    CHECK(near(d, normalize(f.w + f.u)));
    CHECK(f.pixel_angle() == Approx(0.5f * kPi / half_diagonal));
    // Nothing projects onto them: the light tracer's connection finds no pixel.
    float fx, fy;
    CHECK_FALSE(e.project(e.eye + e.w * 5.f, fx, fy));
    CHECK_FALSE(f.project(f.eye + f.w * 5.f, fx, fy));
    CHECK(std::string(camera_type_name(CameraType::Fisheye)) == "fisheye");
}

TEST_CASE("thin lens: every ray of a pixel meets the pinhole ray on the plane in focus",
          "[camera][fast]") {
    Camera c = make(CameraType::Perspective);
    c.lens_radius = 5.f;
    c.focal_distance = 600.f;
    for (const auto& [fx, fy] : {std::pair{256.f, 128.f}, std::pair{10.5f, 200.25f}}) {
        Vec3 o0, d0;
        c.generate(fx, fy, o0, d0);
        const Vec3 focus = o0 + d0 * (c.focal_distance / dot(d0, c.w));
        for (float a : {0.1f, 0.5f, 0.9f}) {
            Vec3 o, d;
            c.generate(fx, fy, {a, 1.f - a * 0.7f}, o, d);
            // The origin lies on the lens disc, the ray passes through the focus point.
            CHECK(dot(o - c.eye, c.w) == Approx(0.f).margin(1e-3));
            CHECK(length(o - c.eye) <= c.lens_radius * 1.0001f);
            const Vec3 p = o + d * (dot(focus - o, c.w) / dot(d, c.w));
            CHECK(length(p - focus) < 1e-2f);
        }
    }
    // project() inverts the pinhole's generate().
    c.lens_radius = 0.f;
    Vec3 o, d;
    c.generate(100.25f, 50.75f, o, d);
    float fx, fy;
    REQUIRE(c.project(o + d * 300.f, fx, fy));
    CHECK(fx == Approx(100.25f).epsilon(1e-4));
    CHECK(fy == Approx(50.75f).epsilon(1e-4));
    CHECK_FALSE(c.project(c.eye - c.w, fx, fy));  // behind the eye
}

namespace {
// M p for a column vector p, with the homogeneous divide (pbrt-v4's convention).
Vec3 transform(const std::array<float, 16>& m, const Vec3& p) {
    double r[4];
    for (int i = 0; i < 4; ++i)
        r[i] = m[std::size_t(i * 4 + 0)] * double(p.x) + m[std::size_t(i * 4 + 1)] * double(p.y) +
               m[std::size_t(i * 4 + 2)] * double(p.z) + m[std::size_t(i * 4 + 3)];
    return Vec3(float(r[0] / r[3]), float(r[1] / r[3]), float(r[2] / r[3]));
}
}  // namespace

TEST_CASE("EXR camera matrices: worldToCamera and worldToNDC agree with the camera's rays",
          "[camera][fast]") {
    for (CameraType type : {CameraType::Perspective, CameraType::Orthographic}) {
        Camera c = make(type);
        c.eye = {1, 2, 3};
        c.target = {-2, 0.5f, -4};
        c.up = {0.1f, 1, 0};
        c.setup();
        const auto to_camera = c.world_to_camera();
        const auto to_ndc = c.world_to_ndc();
        // The eye is the origin, the view direction +z, right +x, up +y.
        const Vec3 e = transform(to_camera, c.eye);
        CHECK(length(e) < 1e-5f);
        const Vec3 ahead = transform(to_camera, c.eye + c.w * 5.f);
        CHECK(ahead.z == Approx(5.f).margin(1e-4));
        CHECK(transform(to_camera, c.eye + c.u).x == Approx(1.f).margin(1e-5));
        CHECK(transform(to_camera, c.eye + c.v).y == Approx(1.f).margin(1e-5));
        // Every point on a pixel's ray lands on that pixel's NDC position, pbrt-v4's: 1/2 plus
        // half the screen position, y up; a perspective screen spans +-1 on the shorter side
        // (256 pixels here), an orthographic one is camera space itself.
        for (const auto& [fx, fy] : {std::pair{0.f, 0.f}, std::pair{512.f, 256.f},
                                     std::pair{100.5f, 30.25f}, std::pair{400.f, 200.f}}) {
            Vec3 o, d;
            c.generate(fx, fy, o, d);
            const float sx = type == CameraType::Perspective ? (fx - 256.f) / 128.f
                                                             : (fx - 256.f) * c.pixel_size;
            const float sy = type == CameraType::Perspective ? (128.f - fy) / 128.f
                                                             : (128.f - fy) * c.pixel_size;
            for (float t : {0.5f, 3.f, 40.f}) {
                const Vec3 ndc = transform(to_ndc, o + d * t);
                CHECK(ndc.x == Approx(0.5f + 0.5f * sx).margin(1e-4));
                CHECK(ndc.y == Approx(0.5f + 0.5f * sy).margin(1e-4));
            }
        }
    }
}
