// Textured emission (Material::emission_texture: MTL's map_Ke, glTF's emissiveTexture): seen
// directly the emitter shows Ke times its texture; lighting a floor, next event estimation
// (which evaluates the texture at the sampled point), BSDF sampling alone, light tracing and
// bdpt agree. And glTF's metallic-roughness texture weights and roughens the metal per hit.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>

#include "engine/film/image_io.h"
#include "engine/scene/pbrt_loader.h"
#include "engine/scene/xml_loader.h"
#include "test_util.h"

using namespace foton;

namespace {

// An 8 x 8 emission map: bright on the left half of u (1, 0.5, 0.25), dark (0.05) on the
// right: mean (0.525, 0.275, 0.15).
void write_emission_map(const std::string& path) {
    Film f(8, 8);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)
            f.pixels[std::size_t(y * 8 + x)] = x < 4 ? RGB{1.f, 0.5f, 0.25f} : RGB{0.05f};
    write_exr(path, f);
}

// A unit quad light at height h facing down (-z), uv over it, Ke = 2 times the map.
void write_light(const test::TempDir& dir, float h) {
    write_emission_map(dir.file("glow.exr"));
    std::ofstream(dir.file("light.mtl")) << "newmtl glow\nKd 0 0 0\nKe 2 2 2\nmap_Ke glow.exr\n";
    std::ofstream(dir.file("light.obj"))
        << "mtllib light.mtl\nv -0.5 -0.5 " << h << "\nv 0.5 -0.5 " << h << "\nv 0.5 0.5 " << h
        << "\nv -0.5 0.5 " << h
        << "\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl glow\nf 1/1 4/4 3/3 2/2\n";
}

std::string scene(const std::string& renderer, const std::string& camera,
                  const std::string& film = R"(<film width="24" height="24"/>)") {
    return R"(<scene><objects>
  <triangle_mesh src="light.obj"/>
  <quad><corner x="-3" y="-3" z="0"/><edge1 x="6" y="0" z="0"/><edge2 x="0" y="6" z="0"/>
    <material type="lambert"><reflectance r="0.5" g="0.5" b="0.5"/></material></quad>
  </objects>)" +
           film + renderer + camera + "</scene>";
}

}  // namespace

TEST_CASE("emission textures: the emitter shows Ke times its texture", "[emission_texture]") {
    test::TempDir dir;
    write_light(dir, 1.f);
    // An orthographic camera under the light looking up at it, the quad filling the view.
    std::ofstream(dir.file("s.xml")) << scene(
        R"(<renderer type="path" max_depth="1"/>)",
        R"(<camera type="orthographic"><eye x="0" y="0" z="0.5"/><target x="0" y="0" z="1"/>
           <up x="0" y="1" z="0"/></camera>)",
        R"(<film width="24" height="24" size="0.041666667"/>)");
    TestScene s(load_scene(dir.file("s.xml")));
    const Film img = render_test(s, 4).film;
    RGB sum{0.f};
    for (const RGB& p : img.pixels) sum += p;
    sum *= 1.f / float(img.pixels.size());
    // 2 x the map's mean, (1.05, 0.55, 0.3).
    CHECK(sum.r == Approx(1.05).epsilon(0.01));
    CHECK(sum.g == Approx(0.55).epsilon(0.01));
    CHECK(sum.b == Approx(0.3).epsilon(0.01));
    // The bright half is (2, 1, 0.5), the dark one 0.1: the texture is read per point.
    float hi = 0.f, lo = 10.f;
    for (const RGB& p : img.pixels) {
        hi = std::max(hi, p.r);
        lo = std::min(lo, p.r);
    }
    CHECK(hi == Approx(2.f).epsilon(0.02));
    CHECK(lo == Approx(0.1f).epsilon(0.05));
}

TEST_CASE("emission textures: light sampling, BSDF sampling, light tracing and bdpt agree",
          "[emission_texture][integrators]") {
    test::TempDir dir;
    write_light(dir, 1.f);
    // Looking straight down at the floor under the light (from between the two; the light
    // tracer needs a pinhole).
    const std::string camera =
        R"(<camera fov="90"><eye x="0" y="0" z="0.5"/><target x="0" y="0" z="0"/>
           <up x="0" y="1" z="0"/></camera>)";
    // The floor's mean red on the image's left and right halves (under the light's bright
    // and dark halves).
    struct Halves {
        float left, right;
    };
    auto halves = [&](const std::string& renderer, uint32_t spp) {
        std::ofstream(dir.file("s.xml")) << scene(renderer, camera);
        TestScene s(load_scene(dir.file("s.xml")));
        const Film img = render_test(s, spp).film;
        double l = 0.0, r = 0.0;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) {
                const RGB& p = img.pixels[std::size_t(y * img.width + x)];
                (x < img.width / 2 ? l : r) += double(p.r);
            }
        const double n = 0.5 * double(img.pixels.size());
        return Halves{float(l / n), float(r / n)};
    };
    const Halves nee = halves(R"(<renderer type="path" max_depth="2"/>)", 256);
    const Halves bsdf = halves(R"(<renderer type="path" max_depth="2" nee="false"/>)", 2048);
    const Halves light = halves(R"(<renderer type="light" max_depth="2"/>)", 512);
    const Halves bdpt = halves(R"(<renderer type="bdpt" max_depth="2"/>)", 128);
    INFO("left/right: nee " << nee.left << " " << nee.right << "; bsdf " << bsdf.left << " "
                            << bsdf.right << "; light " << light.left << " " << light.right
                            << "; bdpt " << bdpt.left << " " << bdpt.right);
    // Under the bright half the floor is brighter: the texture is read where light leaves.
    CHECK(nee.left > 1.2f * nee.right);
    for (const Halves& other : {bsdf, light, bdpt}) {
        CHECK(other.left == Approx(nee.left).epsilon(0.02));
        CHECK(other.right == Approx(nee.right).epsilon(0.02));
    }
}

TEST_CASE("emission textures: pbrt-v4's image area light shows its image at the shape's uv",
          "[emission_texture][pbrt][fast]") {
    test::TempDir dir;
    write_emission_map(dir.file("glow.exr"));
    // The quad faces the camera (+z) and fills the orthographic view; uv over it.
    const std::string head =
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"orthographic\" \"float screenwindow\" "
        "[-0.5 0.5 -0.5 0.5]\nFilm \"rgb\" \"integer xresolution\" [16] \"integer yresolution\" "
        "[16]\nSampler \"independent\" \"integer pixelsamples\" [4]\nIntegrator \"path\" "
        "\"integer maxdepth\" [1]\nWorldBegin\nAttributeBegin\nAreaLightSource \"diffuse\" ";
    const std::string quad =
        "\nShape \"trianglemesh\" \"point3 P\" [-0.5 -0.5 0  0.5 -0.5 0  0.5 0.5 0  -0.5 0.5 0] "
        "\"point2 uv\" [0 0  1 0  1 1  0 1] \"integer indices\" [0 1 2  0 2 3]\nAttributeEnd\n";
    TestScene s(
        parse_pbrt_scene(head + "\"string filename\" \"glow.exr\" \"float scale\" [2]" + quad,
                         "a.pbrt", dir.path().string()));
    REQUIRE(s.materials[s.objects[0].material].emission_texture >= 0);
    const Film img = render_test(s, 4).film;
    // u < 0.5: 2 x (1, 0.5, 0.25); u > 0.5: 2 x 0.05 (pixels away from the seam). pbrt's
    // camera looking down -z with y up has world +x on the image's left.
    for (const int x : {2, 13}) {
        const RGB& p = img.pixels[std::size_t(8 * 16 + x)];
        INFO("pixel " << x << ": " << p.r << " " << p.g << " " << p.b);
        CHECK(p.r == Approx(x > 8 ? 2.f : 0.1f).epsilon(1e-3));
        CHECK(p.b == Approx(x > 8 ? 0.5f : 0.1f).epsilon(1e-3));
    }
    CHECK_THROWS_WITH(
        parse_pbrt_scene(head + "\"string filename\" \"glow.exr\" \"rgb L\" [1 1 1]" + quad,
                         "b.pbrt", dir.path().string()),
        Catch::Contains("b.pbrt:8") && Catch::Contains("not both"));
}
