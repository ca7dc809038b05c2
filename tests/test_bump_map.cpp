// Bump mapping (Material::bump, pbrt-v4's BumpMap in surface_at) and roughness textures
// (Material::float_params): a displacement ramp tilts a plane's normal by its slope, a
// sphere's by the radial displacement's exact normal, a constant one leaves a sphere's
// normal radial; a Lambertian floor follows the bumped normal's cosine; a roughness texture
// sets the lobe's alpha at each hit, as the constant roughness it holds would; the pbrt-v4
// importer and the XML read both, and bad input fails at its line.
#include <catch2/catch.hpp>
#include <cmath>

#include "engine/core/error.h"
#include "engine/film/image_io.h"
#include "engine/scene/pbrt_loader.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/common/shading_normal.h"
#include "engine/transport/common/surface.h"
#include "lit_floor_scene.h"
#include "test_util.h"

using namespace foton;

namespace {

// A grey ramp whose bilinear lookup is d(u) = u (along_u) or d(v) = v, exactly, away from the
// image's wrapping edges: texel centres at (i + 0.5) / n hold that coordinate.
std::string write_ramp(const test::TempDir& dir, const std::string& name, bool along_u) {
    const int n = 64;
    Film f(along_u ? n : 1, along_u ? 1 : n);
    for (int i = 0; i < n; ++i) {
        // Row 0 is the image's top, v = 1.
        const float c = along_u ? (float(i) + 0.5f) / float(n) : 1.f - (float(i) + 0.5f) / float(n);
        f.pixels[std::size_t(i)] = RGB{c};
    }
    const std::string path = dir.file(name);
    write_exr(path, f);
    return path;
}

// A constant 4 x 4 image of value c.
std::string write_flat(const test::TempDir& dir, const std::string& name, float c) {
    Film f(4, 4);
    for (RGB& p : f.pixels) p = RGB{c};
    const std::string path = dir.file(name);
    write_exr(path, f);
    return path;
}

// The shared lit floor (lit_floor_scene.h), its Lambert bumped by `bump` ("" for none).
std::string floor_scene(const std::string& textures, const std::string& bump, const Vec3& l) {
    return test::lit_floor_scene(
        textures, bump.empty() ? std::string() : "\"texture displacement\" \"" + bump + "\"", l);
}

std::string ramp_texture(const std::string& path, float scale) {
    return "Texture \"d\" \"float\" \"imagemap\" \"string filename\" \"" + path +
           "\" \"float scale\" [" + std::to_string(scale) + "]\n";
}

Vec3 floor_normal(const Scene& s) {
    // A ray straight down onto the first triangle, at uv (0.5, 0.2).
    return surface_at(s, 0, 0, 5.f, 0.3f, 0.2f, {10.f, -20.f, 5.f}, {0.f, 0.f, -1.f}).ns;
}

}  // namespace

TEST_CASE("bump maps: a displacement ramp tilts a plane's normal by its slope", "[bump][fast]") {
    test::TempDir dir;
    const std::string ramp = write_ramp(dir, "ramp.exr", true);
    // d = a u over a floor 100 long in u: the displaced floor rises a over 100, its normal is
    // (-a, 0, 100) normalised.
    for (const float a : {10.f, 50.f, -30.f}) {
        const Scene s =
            parse_pbrt_scene(floor_scene(ramp_texture(ramp, a), "d", {0, 0, 1}), "f.pbrt", ".");
        REQUIRE(s.materials.back().bump >= 0);
        const Vec3 n = floor_normal(s), want = normalize(Vec3{-a, 0.f, 100.f});
        INFO("slope " << a);
        CHECK(n.x == Approx(want.x).margin(1e-4));
        CHECK(n.y == Approx(0.f).margin(1e-4));
        CHECK(n.z == Approx(want.z).margin(1e-4));
    }
    // A scale texture of the ramp folds its factor into it.
    const Scene scaled =
        parse_pbrt_scene(floor_scene(ramp_texture(ramp, 1.f) +
                                         "Texture \"d2\" \"float\" \"scale\" \"texture tex\" \"d\" "
                                         "\"float scale\" [20]\n",
                                     "d2", {0, 0, 1}),
                         "f.pbrt", ".");
    CHECK(floor_normal(scaled).x == Approx(normalize(Vec3{-20.f, 0.f, 100.f}).x).margin(1e-4));
    // A flat texture: no change.
    const std::string flat = write_flat(dir, "flat.exr", 0.7f);
    const Scene s = parse_pbrt_scene(
        floor_scene("Texture \"d\" \"float\" \"imagemap\" \"string filename\" \"" + flat + "\"\n",
                    "d", {0, 0, 1}),
        "f.pbrt", ".");
    CHECK(floor_normal(s).z == Approx(1.f));
}

TEST_CASE("bump maps: a sphere's bumped normal is the displaced sphere's", "[bump][xml][fast]") {
    test::TempDir dir;
    write_ramp(dir, "vramp.exr", false);
    write_flat(dir, "flat.exr", 1.f);
    auto scene = [&](const std::string& bump) {
        return parse_scene(
            "<scene><objects><sphere radius=\"1\"><center x=\"0\" y=\"0\" z=\"0\"/>"
            "<material type=\"lambert\">" +
                bump +
                "</material></sphere></objects><film width=\"4\" height=\"4\"/><camera><eye "
                "x=\"0\" y=\"0\" z=\"-5\"/><target x=\"0\" y=\"0\" z=\"0\"/></camera></scene>",
            "b.xml", dir.path().string());
    };
    // A ray along -x hits (1, 0, 0): phi 0, theta pi/2, v = 0.5.
    auto normal = [&](const Scene& s) {
        return surface_at(s, 0, 0, 4.f, 0.f, 0.f, {5.f, 0.f, 0.f}, {-1.f, 0.f, 0.f}).ns;
    };
    // A constant displacement moves the sphere out without turning its normal (the d dn/du
    // terms keep it radial).
    const Vec3 n0 = normal(scene(R"(<bump src="flat.exr" scale="0.3"/>)"));
    CHECK(n0.x == Approx(1.f).margin(1e-4));
    CHECK(std::fabs(n0.z) < 1e-4f);
    // d = a v with v = 1 - theta / pi: the radius R(theta) = 1 + a v has the normal
    // R e_r - R' e_theta = R e_r + (a / pi) e_theta, and e_theta = -z at the equator.
    const float a = 0.4f;
    const Vec3 n1 = normal(scene(R"(<bump src="vramp.exr" scale="0.4"/>)"));
    const Vec3 want = normalize(Vec3{1.f + 0.5f * a, 0.f, -a / kPi});
    CHECK(n1.x == Approx(want.x).margin(1e-4));
    CHECK(n1.y == Approx(0.f).margin(1e-4));
    CHECK(n1.z == Approx(want.z).margin(1e-4));
    CHECK_THROWS_WITH(scene(R"(<bump src="vramp.exr"/>)"),
                      Catch::Contains("b.xml:1") && Catch::Contains("scale"));
}

TEST_CASE("bump maps: a Lambertian floor under a distant light follows the bumped normal",
          "[bump]") {
    test::TempDir dir;
    const std::string ramp = write_ramp(dir, "ramp.exr", true);
    const Vec3 l = normalize(Vec3{0.6f, 0.f, 0.8f});
    for (const float a : {0.f, 40.f, -40.f}) {
        TestScene s(parse_pbrt_scene(floor_scene(ramp_texture(ramp, a), a == 0.f ? "" : "d", l),
                                     "f.pbrt", "."));
        const Film img = render_test(s, 4).film;
        RGB sum{0.f};
        for (const RGB& p : img.pixels) sum += p;
        const double mean = sum.g / double(img.pixels.size());
        const Vec3 n = normalize(Vec3{-a, 0.f, 100.f});
        INFO("slope " << a);
        CHECK(mean == Approx(0.5 / kPi * double(dot(n, l))).epsilon(1e-3));
    }
}

TEST_CASE("roughness textures: the lobe's alpha at a hit is the texture's value there",
          "[bump][roughness_texture][fast]") {
    test::TempDir dir;
    const std::string quarter = write_flat(dir, "quarter.exr", 0.25f);
    const std::string ramp = write_ramp(dir, "ramp.exr", true);
    auto floor = [&](const std::string& textures, const std::string& material) {
        return parse_pbrt_scene(
            "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\n"
            "Film \"rgb\" \"integer xresolution\" [4] \"integer yresolution\" [4]\nWorldBegin\n" +
                textures + material +
                "\nShape \"trianglemesh\" \"point3 P\" [-50 -50 0  50 -50 0  50 50 0  -50 50 0]\n"
                "  \"point2 uv\" [0 0  1 0  1 1  0 1] \"integer indices\" [0 1 2  0 2 3]\n",
            "r.pbrt", ".");
    };
    const std::string tex =
        "Texture \"r\" \"float\" \"imagemap\" \"string filename\" \"" + quarter + "\"\n" +
        "Texture \"ramp\" \"float\" \"imagemap\" \"string filename\" \"" + ramp + "\"\n";
    auto lobe_at = [](const Scene& s, Point2 uv, std::optional<Material>& scratch) {
        return s.material_at(0, uv, scratch).bsdf.lobe(0);
    };
    std::optional<Material> a, b;
    // Remapped (pbrt's default): roughness 0.25 is alpha 0.5, as the constant would give.
    const Scene textured = floor(tex, "Material \"conductor\" \"texture roughness\" \"r\"");
    const Scene constant = floor(tex, "Material \"conductor\" \"float roughness\" [0.25]");
    REQUIRE(textured.materials.back().num_float_params == 2);
    const Lobe lt = lobe_at(textured, {0.3f, 0.6f}, a), lc = lobe_at(constant, {0.3f, 0.6f}, b);
    CHECK(lt.type == LobeType::Microfacet);
    CHECK(lc.type == LobeType::Microfacet);
    CHECK(lt.dist.alpha == Approx(0.5f));
    CHECK(lt.dist.alpha_y == Approx(0.5f));
    const BsdfContext ctx;
    const Vec3 wo = normalize(Vec3{0.3f, 0.1f, 0.9f}), wi = normalize(Vec3{-0.2f, 0.4f, 0.8f});
    const RGB ft = textured.material_at(0, {0.3f, 0.6f}, a).bsdf.f(wo, wi, ctx);
    const RGB fc = constant.material_at(0, {0.3f, 0.6f}, b).bsdf.f(wo, wi, ctx);
    CHECK(ft.g == Approx(fc.g).epsilon(1e-6));
    // Anisotropic: a texture on u only, a constant v; not remapped: the ramp is alpha = u.
    const Scene aniso = floor(tex,
                              "Material \"conductor\" \"texture uroughness\" \"ramp\" "
                              "\"float vroughness\" [0.09] \"bool remaproughness\" false");
    const Lobe la = lobe_at(aniso, {0.4f, 0.5f}, a);
    CHECK(la.dist.alpha == Approx(0.4f).margin(1e-4));
    CHECK(la.dist.alpha_y == Approx(0.09f));
    // A rough dielectric and a coat read theirs.
    const Lobe ld =
        lobe_at(floor(tex, "Material \"dielectric\" \"texture roughness\" \"r\""), {0.5f, 0.5f}, a);
    CHECK(ld.type == LobeType::RoughDielectric);
    CHECK(ld.dist.alpha == Approx(0.5f));
    const Lobe lk = lobe_at(floor(tex,
                                  "Material \"coatedconductor\" \"texture interface.roughness\" "
                                  "\"r\" \"texture conductor.roughness\" \"ramp\" "
                                  "\"bool remaproughness\" false"),
                            {0.7f, 0.5f}, a);
    CHECK(!lk.coat.coat_smooth);
    CHECK(lk.coat.coat.alpha == Approx(0.25f));
    CHECK(lk.dist.alpha == Approx(0.7f).margin(1e-4));
    // A varying texture where foton takes only constants fails at its line.
    CHECK_THROWS_WITH(floor(tex, "Material \"coateddiffuse\"\n  \"texture thickness\" \"r\""),
                      Catch::Contains("r.pbrt:8") && Catch::Contains("thickness"));
    CHECK_THROWS_WITH(floor(tex, "Material \"diffuse\" \"texture displacement\" \"nothing\""),
                      Catch::Contains("r.pbrt:7") && Catch::Contains("unknown float texture"));
}

TEST_CASE("roughness textures: the XML's <roughness_map> sets a rough lobe's alpha",
          "[roughness_texture][xml][fast]") {
    test::TempDir dir;
    write_ramp(dir, "ramp.exr", true);
    auto scene = [&](const std::string& material) {
        return parse_scene(
            "<scene><objects><sphere radius=\"1\"><center x=\"0\" y=\"0\" z=\"0\"/>" + material +
                "</sphere></objects><film width=\"4\" height=\"4\"/><camera><eye x=\"0\" "
                "y=\"0\" z=\"-5\"/><target x=\"0\" y=\"0\" z=\"0\"/></camera></scene>",
            "r.xml", dir.path().string());
    };
    const Scene s = scene(R"(<material type="conductor" roughness="0.3" distribution="ggx">
        <roughness_map src="ramp.exr" scale="0.5"/></material>)");
    std::optional<Material> scratch;
    const Lobe l = s.material_at(0, {0.6f, 0.5f}, scratch).bsdf.lobe(0);
    CHECK(l.dist.alpha == Approx(0.3f).margin(1e-4));
    CHECK(l.dist.alpha_y == Approx(0.3f).margin(1e-4));
    CHECK_THROWS_WITH(scene(R"(<material type="conductor"><roughness_map src="ramp.exr"/>
        </material>)"),
                      Catch::Contains("r.xml:1") && Catch::Contains("rough lobe"));
}

TEST_CASE("shading normals: triangle partials are those of the linear parametrisation",
          "[bump][fast]") {
    // p = (2u + v, 3v, u) over a triangle: dp/du = (2, 0, 1), dp/dv = (1, 3, 0).
    auto p = [](float u, float v) { return Vec3{2.f * u + v, 3.f * v, u}; };
    const Point2 t0{0.1f, 0.2f}, t1{0.9f, 0.3f}, t2{0.4f, 0.8f};
    Vec3 dpdu, dpdv;
    REQUIRE(triangle_partials(p(t0.x, t0.y), p(t1.x, t1.y), p(t2.x, t2.y), t0, t1, t2, dpdu, dpdv));
    CHECK(dpdu.x == Approx(2.f));
    CHECK(dpdu.y == Approx(0.f).margin(1e-5));
    CHECK(dpdu.z == Approx(1.f));
    CHECK(dpdv.x == Approx(1.f));
    CHECK(dpdv.y == Approx(3.f));
    CHECK(dpdv.z == Approx(0.f).margin(1e-5));
    CHECK_FALSE(triangle_partials(p(0, 0), p(1, 1), p(2, 2), {0, 0}, {1, 1}, {2, 2}, dpdu, dpdv));
}

TEST_CASE("anisotropic lobes: the shading frame's x axis is the surface's dp/du",
          "[bump][anisotropic][fast]") {
    // pbrt-v4's convention: uroughness runs along dp/du. A floor with u along +x, and a
    // sphere (u around z): at (1, 0, 0) dp/du is +y.
    const Scene floor = parse_pbrt_scene(
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
        "Material \"conductor\" \"float uroughness\" [0.05] \"float vroughness\" [0.3]\n"
        "Shape \"trianglemesh\" \"point3 P\" [-50 -50 0  50 -50 0  50 50 0  -50 50 0]\n"
        "  \"point2 uv\" [0 0  1 0  1 1  0 1] \"integer indices\" [0 1 2  0 2 3]\n"
        "AttributeBegin\nTranslate 0 0 -20\n"
        "Material \"dielectric\" \"float uroughness\" [0.05] \"float vroughness\" [0.3]\n"
        "Shape \"sphere\" \"float radius\" [1]\nAttributeEnd\n",
        "a.pbrt", ".");
    REQUIRE(floor.materials[floor.objects[0].material].needs_tangent());
    const SurfacePoint f =
        surface_at(floor, 0, 0, 5.f, 0.3f, 0.2f, {10.f, -20.f, 5.f}, {0.f, 0.f, -1.f});
    CHECK(f.ss.x == Approx(1.f));
    const warp::Frame fr = f.frame();
    CHECK(fr.to_local(Vec3{1.f, 0.f, 0.f}).x == Approx(1.f));
    CHECK(fr.to_local(f.ns).z == Approx(1.f));
    const SurfacePoint s =
        surface_at(floor, 1, 0, 4.f, 0.f, 0.f, {5.f, 0.f, -20.f}, {-1.f, 0.f, 0.f});
    CHECK(s.ss.y == Approx(1.f));
    CHECK(std::fabs(dot(s.ss, s.ns)) < 1e-6f);
    // An isotropic material has no tangent: the frame is the normal's own basis, as before.
    const Scene iso = parse_pbrt_scene(
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
        "Material \"conductor\" \"float roughness\" [0.1]\n"
        "Shape \"sphere\" \"float radius\" [1]\n",
        "i.pbrt", ".");
    CHECK_FALSE(iso.materials.back().needs_tangent());
    const SurfacePoint si = surface_at(iso, 0, 0, 4.f, 0.f, 0.f, {5.f, 0.f, 0.f}, {-1.f, 0.f, 0.f});
    CHECK(length(si.ss) == 0.f);
}
