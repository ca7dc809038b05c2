#pragma once
// A flat model file seen head-on: the unit square [0, 1]^2 at z = 0 filling an orthographic
// camera's 64 x 64 image, lit by a distant light of irradiance pi, so a Lambertian point's
// radiance is its albedo; and the worst pixel of its render against what the file says.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <functional>
#include <string>

#include "engine/accel/intersector.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/render.h"
#include "test_util.h"

namespace foton::test {

// The scene around a mesh file: the unit square [0, 1]^2 at z = 0 seen from +z by an
// orthographic camera that it fills, lit head-on by a distant light of irradiance pi, so a
// Lambertian point's radiance is its albedo.
inline void write_scene(const std::string& path, const std::string& mesh) {
    std::ofstream(path) << R"(<scene>
  <lights><directional intensity="3.14159265"><direction x="0" y="0" z="-1"/></directional></lights>
  <objects>)" << mesh << R"(</objects>
  <film width="64" height="64" size="0.015625"/>
  <renderer type="path" max_depth="1" sampler="jittered"/>
  <camera type="orthographic"><eye x="0.5" y="0.5" z="5"/><target x="0.5" y="0.5" z="0"/></camera>
</scene>)";
}

// Renders the scene and returns the largest difference between a pixel and `want` averaged
// over the pixel (8 x 8 points, each given the point of the plane z = 0 it sees).
inline double worst_pixel(const std::string& scene_path,
                          const std::function<RGB(float, float)>& want) {
    TestScene s(load_scene(scene_path));
    const auto acc = make_intersector(s, s.accel);
    RenderOptions opt = s.render.run;
    opt.spp = 16;
    const Film f = render(s, s.render, *acc, opt).film;
    double worst = 0.0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            RGB w{0.f};
            for (int j = 0; j < 8; ++j)
                for (int i = 0; i < 8; ++i) {
                    Vec3 o, d;
                    s.camera.generate(float(x) + (float(i) + 0.5f) / 8.f,
                                      float(y) + (float(j) + 0.5f) / 8.f, o, d);
                    const Vec3 q = o + d * (-o.z / d.z);
                    w += want(q.x, q.y) * (1.f / 64.f);
                }
            const RGB& got = f.pixels[std::size_t(y) * 64 + std::size_t(x)];
            const double d =
                std::max({double(std::fabs(got.r - w.r)), double(std::fabs(got.g - w.g)),
                          double(std::fabs(got.b - w.b))});
            if (d > worst)
                UNSCOPED_INFO("pixel " << x << "," << y << " got " << got.r << " " << got.g << " "
                                       << got.b << " want " << w.r << " " << w.g << " " << w.b);
            worst = std::max(worst, d);
        }
    return worst;
}

}  // namespace foton::test
