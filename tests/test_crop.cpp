// Crop windows: a window renders exactly the full image's pixels there, for every integrator
// whose pixels do not depend on the others (the irradiance cache's records do).
#include <catch2/catch.hpp>
#include <cstring>

#include "engine/accel/intersector.h"
#include "engine/film/image_io.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/render.h"
#include "test_util.h"

using namespace foton;

TEST_CASE("a crop window's pixels equal the full render's, bit for bit", "[crop][fast]") {
    struct Case {
        const char* scene;
        const char* type;
        bool adaptive;
        SamplerKind sampler = SamplerKind::Jittered;
        bool gaussian = false;  // pbrt-v4's default pixel filter: splats reach past the crop
    };
    // zsobol orders the pixels of the full image: a crop draws the same samples.
    for (const Case c :
         {Case{"scenes/cornell-diffuse.xml", "path", false},
          Case{"scenes/cornell-diffuse.xml", "path", true},
          Case{"scenes/cornell-diffuse.xml", "path", false, SamplerKind::ZSobol},
          Case{"scenes/materials.xml", "distributed", false},
          Case{"scenes/cornell-box.xml", "raytracer", false},
          Case{"scenes/cornell-caustics.xml", "light", false},
          Case{"scenes/cornell-caustics.xml", "photon", false},
          Case{"scenes/cornell-caustics.xml", "sppm", false},
          Case{"scenes/cornell-caustics.xml", "bdpt", false},
          Case{"scenes/cornell-caustics.xml", "vcm", false},
          Case{"scenes/cornell-diffuse.xml", "path", false, SamplerKind::Sobol, true},
          Case{"scenes/cornell-caustics.xml", "light", false, SamplerKind::Jittered, true},
          Case{"scenes/cornell-caustics.xml", "bdpt", false, SamplerKind::Jittered, true}}) {
        INFO(c.scene << " " << c.type << (c.adaptive ? " adaptive " : " ")
                     << sampler_name(c.sampler) << (c.gaussian ? " gaussian" : ""));
        TestScene full = load_scene(test::source_path(c.scene));
        full.set_resolution(32, 24);
        full.render.integrator = c.type;
        full.render.sampler = c.sampler;
        full.render.photon.global_photons = 4000;
        full.render.photon.caustic_photons = 4000;
        full.render.photon.gather_rays = 4;
        if (c.gaussian) full.film.filter = PixelFilter::gaussian(1.5f, 1.5f, 0.5f);
        if (c.adaptive) {
            full.render.adaptive.enabled = true;
            full.render.adaptive.pilot = 2;
            full.render.adaptive.max_spp = 8;
            full.render.adaptive.threshold = 0.05f;
        }
        TestScene crop = full;
        crop.set_crop(5, 21, 3, 17);
        REQUIRE(crop.film.width == 16);
        REQUIRE(crop.film.height == 14);
        const auto accel = make_intersector(full, AccelType::Bvh, 2);
        RenderOptions opt;
        opt.spp = 2;
        opt.seed = 11;
        opt.threads = 2;
        const RenderResult a = render(full, full.render, *accel, opt);
        const RenderResult b = render(crop, crop.render, *accel, opt);
        REQUIRE(b.film.width == 16);
        int differing = 0;
        for (int y = 0; y < 14; ++y)
            for (int x = 0; x < 16; ++x) {
                const RGB& p = a.film.at(5 + x, 3 + y);
                const RGB& q = b.film.at(x, y);
                differing += std::memcmp(&p, &q, sizeof p) != 0;
            }
        CHECK(differing == 0);
    }
}

TEST_CASE("a crop is written as the data window of the full image", "[crop][fast]") {
    test::TempDir dir;
    Film f(4, 3);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 4; ++x) f.at(x, y) = RGB(float(x), float(y), 1.f);
    ExrRenderInfo info;
    info.x0 = 7;
    info.y0 = 2;
    info.display_width = 20;
    info.display_height = 10;
    write_exr(dir.file("c.exr"), f, {}, info);
    const Film back = read_exr(dir.file("c.exr"));
    REQUIRE(back.width == 4);
    REQUIRE(back.height == 3);
    CHECK(std::memcmp(back.pixels.data(), f.pixels.data(), f.pixels.size() * sizeof(RGB)) == 0);
}
