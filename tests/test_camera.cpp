#include <catch2/catch.hpp>

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

TEST_CASE("perspective camera rays for known pixels", "[camera]") {
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

TEST_CASE("orthographic camera rays are parallel and offset on the view plane", "[camera]") {
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
