// The pbrt-v4 importer: the refs' Cornell boxes against pbrt-v4's images, the camera and
// transform conventions, orientation rules, materials, lights, spectra, warnings for what
// is left out and file:line errors for what cannot be rendered.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <tuple>

#include "engine/accel/intersector.h"
#include "engine/core/error.h"
#include "engine/film/image_io.h"
#include "engine/film/metrics.h"
#include "engine/scene/pbrt/spectrum.h"
#include "engine/scene/pbrt_loader.h"
#include "engine/scene/texture.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/render.h"
#include "test_util.h"

using namespace foton;

namespace {

Scene import_text(const std::string& body, const std::string& base = ".") {
    return parse_pbrt_scene(body, "test.pbrt", base);
}

// A pbrt file: options, then a world with `world` and a floor, so that it has a shape.
Scene world(const std::string& options, const std::string& world) {
    return import_text(
        options + "\nWorldBegin\n" + world +
        "\nShape \"trianglemesh\" \"point3 P\" [-10 -1 -10  10 -1 -10  10 -1 10  -10 -1 "
        "10] \"integer indices\" [0 1 2 0 2 3]\n");
}

// The head of a pbrt file that sees the unit square z = 0 head-on through an orthographic
// camera at `res` x `res` pixels under irradiance pi: a Lambertian surface there shows its
// albedo as its radiance.
std::string head_on_unit_square(int res, const std::string& options = "") {
    const std::string r = std::to_string(res);
    return "Scale -1 1 1\nLookAt 0.5 0.5 5  0.5 0.5 0  0 1 0\n"
           "Camera \"orthographic\" \"float screenwindow\" [-0.5 0.5 -0.5 0.5]\n"
           "Film \"rgb\" \"integer xresolution\" " +
           r + " \"integer yresolution\" " + r + "\n" + options +
           "Integrator \"path\" \"integer maxdepth\" 1\nWorldBegin\n"
           "LightSource \"distant\" \"point3 from\" [0 0 1] \"point3 to\" [0 0 0] "
           "\"rgb L\" [3.14159265 3.14159265 3.14159265]\n";
}

std::string error_of(const std::string& body) {
    try {
        import_text(body);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

Film render_at(Scene s, int size, uint32_t spp) {
    s.set_resolution(size, size);
    s.renderer.set("sampler", "jittered", "test", 0);
    TestScene ts(std::move(s));
    const auto acc = make_intersector(ts, ts.accel);
    RenderOptions opt = ts.render.run;
    opt.spp = spp;
    opt.seed = 1;
    return render(ts, ts.render, *acc, opt).film;
}

}  // namespace

TEST_CASE("pbrt-v4: the refs' Cornell boxes import and match pbrt-v4's images",
          "[pbrt][reference]") {
    struct Case {
        const char* file;
        const char* ref;
        uint32_t spp;
        double mean_tol, block_tol;
        int block;
    };
    // Means: 1 % on the diffuse box; the caustics reference carries SPPM's +0.1..0.5 % blur
    // bias and 256 spp leave the caustic noisy, so 1.5 % there (0.7 % at 512 spp, measured).
    for (const Case& c :
         {Case{"path_diffuse.pbrt", "cornell_diffuse_path_512spp.exr", 64, 0.01, 0.04, 16},
          Case{"path_caustics.pbrt", "cornell_caustics_sppm_256it.exr", 256, 0.015, 0.06, 32}}) {
        INFO(c.file);
        const Scene s = load_scene(test::source_path(std::string("scenes/pbrt/cornell/") + c.file));
        CHECK(s.warnings.empty());
        const Film ref = downsample(read_exr(test::shared_path(std::string("refs/") + c.ref)), 4);
        const std::vector<uint8_t> mask = luminance_mask(ref, 2.f);
        const Film img = render_at(s, 128, c.spp);
        const ImageError e = compare_images(img, ref, &mask);
        INFO("means " << e.mean_a.r << " " << e.mean_a.g << " " << e.mean_a.b << " ref "
                      << e.mean_b.r << " " << e.mean_b.g << " " << e.mean_b.b << " rmse "
                      << e.rmse);
        CHECK(e.mean_a.r == Approx(e.mean_b.r).epsilon(c.mean_tol));
        CHECK(e.mean_a.g == Approx(e.mean_b.g).epsilon(c.mean_tol));
        CHECK(e.mean_a.b == Approx(e.mean_b.b).epsilon(c.mean_tol));
        // Blocks: the red wall on the left, the light where pbrt has it.
        const Film ib = downsample(img, c.block), rb = downsample(ref, c.block);
        double worst = 0.0;
        for (std::size_t i = 0; i < rb.pixels.size(); ++i)
            worst = std::max(worst, std::fabs(double(ib.pixels[i].luminance()) /
                                                  double(rb.pixels[i].luminance()) -
                                              1.0));
        INFO("worst block " << worst);
        CHECK(worst < c.block_tol);
    }
}

TEST_CASE("pbrt-v4: camera conventions (LookAt, fov on the short side, handedness)",
          "[pbrt][fast]") {
    const Scene s = world(R"(LookAt 0 0 -5  0 0 0  0 1 0
        Camera "perspective" "float fov" [ 60 ]
        Film "rgb" "integer xresolution" [ 200 ] "integer yresolution" [ 100 ])",
                          "");
    const Camera& c = s.camera;
    CHECK(s.film.width == 200);
    CHECK(s.film.height == 100);
    // The fov spans the shorter (vertical) side.
    CHECK(c.vertical_fov_degrees() == Approx(60.0).epsilon(1e-4));
    // pbrt's camera space is left-handed: world +x (camera +x) is on the image's right.
    float fx = 0, fy = 0;
    REQUIRE(c.project({1, 0, 0}, fx, fy));
    CHECK(fx > 100.f);
    REQUIRE(c.project({0, 1, 0}, fx, fy));
    CHECK(fy < 50.f);
    // Scale -1 1 1 mirrors it (as the refs' scenes do to put the red wall on the left).
    const Scene m = world(R"(Scale -1 1 1 LookAt 0 0 -5  0 0 0  0 1 0 Camera "perspective")", "");
    REQUIRE(m.camera.project({1, 0, 0}, fx, fy));
    CHECK(fx < 640.f);
    CHECK(m.film.width == 1280);  // pbrt's default film
}

TEST_CASE("pbrt-v4: transforms, attributes, coordinate systems and instances", "[pbrt][fast]") {
    const Scene s = world("", R"(
        AttributeBegin
          Translate 1 2 3
          Scale 2 2 2
          Shape "sphere" "float radius" [ 0.5 ]
          CoordinateSystem "here"
        AttributeEnd
        Shape "sphere"
        TransformBegin
          Rotate 90 0 0 1
          Translate 1 0 0
          Shape "sphere" "float radius" [ 0.25 ]
        TransformEnd
        AttributeBegin
          CoordSysTransform "here"
          ConcatTransform [ 1 0 0 0  0 1 0 0  0 0 1 0  1 0 0 1 ]
          Shape "sphere"
        AttributeEnd
        ObjectBegin "pair"
          Shape "sphere" "float radius" [ 0.1 ]
          Translate 0 0 1
          Shape "sphere" "float radius" [ 0.1 ]
        ObjectEnd
        AttributeBegin Translate 5 0 0 ObjectInstance "pair" AttributeEnd
        AttributeBegin Translate -5 0 0 ObjectInstance "pair" AttributeEnd
    )");
    REQUIRE(s.spheres.size() == 8);
    auto near = [](const Vec3& a, const Vec3& b) { return length(a - b) < 1e-5f; };
    CHECK(near(s.spheres[0].center, {1, 2, 3}));
    CHECK(s.spheres[0].radius == Approx(1.f));
    CHECK(near(s.spheres[1].center, {0, 0, 0}));
    CHECK(near(s.spheres[2].center, {0, 1, 0}));  // translate, then rotate about z
    CHECK(near(s.spheres[3].center, {3, 2, 3}));  // "here" then a column-major translation
    CHECK(s.spheres[3].radius == Approx(2.f));
    CHECK(near(s.spheres[4].center, {5, 0, 0}));
    CHECK(near(s.spheres[5].center, {5, 0, 1}));
    CHECK(near(s.spheres[6].center, {-5, 0, 0}));
    CHECK(near(s.spheres[7].center, {-5, 0, 1}));
    CHECK(s.spheres[7].radius == Approx(0.1f));
    CHECK(s.warnings.empty());
}

TEST_CASE("pbrt-v4: object instances share one mesh, placed by their transforms",
          "[pbrt][instance][fast]") {
    const Scene s = import_text(R"(WorldBegin
        ObjectBegin "tri"
          Translate 0 0 1
          Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "integer indices" [0 1 2]
        ObjectEnd
        AttributeBegin Translate 5 0 0 ObjectInstance "tri" AttributeEnd
        AttributeBegin Scale -2 2 2 ObjectInstance "tri" AttributeEnd
        ObjectInstance "tri"
        Shape "sphere")");
    REQUIRE(s.instances.size() == 3);
    CHECK(s.meshes.size() == 1);
    CHECK(s.num_triangles() == 3);
    CHECK(s.num_stored_triangles() == 1);
    // Definition-time and instance transforms compose, as in pbrt-v4.
    const Bounds3 a = s.object_bounds(0), b = s.object_bounds(1);
    CHECK(a.lo.x == Approx(5.f));
    CHECK(a.lo.z == Approx(1.f));
    CHECK(b.lo.x == Approx(-2.f));
    CHECK(b.hi.z == Approx(2.f));
    // A mirrored placement keeps the outward (winding) normal: world corners are re-wound.
    Vec3 p0, p1, p2;
    s.world_corners(1, 0, p0, p1, p2);
    CHECK(cross(p1 - p0, p2 - p0).z > 0.f);
}

TEST_CASE("pbrt-v4: emitting side and ReverseOrientation follow pbrt", "[pbrt][fast]") {
    // A quad whose winding faces +y; N, when given, decides the side; ReverseOrientation
    // flips it.
    auto normal_of = [](const std::string& before, const std::string& normals) {
        const Scene s = import_text("WorldBegin\n" + before + R"(
            AreaLightSource "diffuse" "rgb L" [1 1 1]
            Shape "trianglemesh" "point3 P" [0 0 0  0 0 1  1 0 1  1 0 0]
            "integer indices" [0 1 2 0 2 3] )" +
                                    normals);
        Vec3 p0, p1, p2;
        s.meshes[0].corners(0, p0, p1, p2);
        return normalize(cross(p1 - p0, p2 - p0));
    };
    CHECK(normal_of("", "").y == Approx(1.f));
    CHECK(normal_of("ReverseOrientation", "").y == Approx(-1.f));
    CHECK(normal_of("", R"("normal N" [0 -1 0 0 -1 0 0 -1 0 0 -1 0])").y == Approx(-1.f));
    CHECK(normal_of("ReverseOrientation", R"("normal N" [0 -1 0 0 -1 0 0 -1 0 0 -1 0])").y ==
          Approx(1.f));
    CHECK(normal_of("Scale 1 1 -1", "").y == Approx(1.f));  // a mirror keeps it outward
}

TEST_CASE("pbrt-v4: materials, named materials, textures and lights", "[pbrt][fast]") {
    const Scene s = world(R"(Integrator "sppm" "integer iterations" [ 7 ] "float radius" [ 2 ])",
                          R"(
        Texture "grey" "spectrum" "constant" "rgb value" [0.25 0.5 0.75]
        Texture "half" "float" "constant" "float value" [0.5]
        Texture "scaled" "spectrum" "scale" "texture tex" "grey" "texture scale" "half"
        MakeNamedMaterial "gold" "string type" "conductor"
            "spectrum eta" "metal-Au-eta" "spectrum k" "metal-Au-k"
        MakeNamedMaterial "matte" "string type" "diffuse" "texture reflectance" "scaled"
        Material "mix" "string materials" ["gold" "matte"] "float amount" 0.25
        Shape "sphere"
        NamedMaterial "matte" Shape "sphere"
        Material "coateddiffuse" "rgb reflectance" [0.5 0.5 0.5] "float roughness" 0
            "float thickness" 0.1 "rgb albedo" [0.2 0.3 0.4] "float g" 0.5 "integer maxdepth" 7
        Shape "sphere"
        Material "dielectric" "spectrum eta" "glass-BK7" Shape "sphere"
        Material "coatedconductor" "float interface.eta" 1.6 "float interface.roughness" 0.09
            "spectrum conductor.eta" "metal-Au-eta" "spectrum conductor.k" "metal-Au-k"
            "float conductor.uroughness" 0.04 "float conductor.vroughness" 0.16
        Shape "sphere"
        LightSource "point" "rgb I" [1 2 3] "point3 from" [0 4 0]
        LightSource "spot" "blackbody I" [3000] "float power" [100] "float coneangle" [20]
        LightSource "distant" "point3 to" [0 -1 0] "float illuminance" [3]
    )");
    REQUIRE(s.spheres.size() == 5);
    auto sphere_material = [&](std::size_t i) -> const Material& {
        for (const Object& o : s.objects)
            if (o.kind == ObjectKind::Sphere && o.index == i) return s.materials[o.material];
        FAIL("no sphere " << i);
        return s.materials[0];
    };
    // mix: 0.75 gold mirror + 0.25 Lambert of 0.5 x (0.25, 0.5, 0.75).
    const Bsdf& m0 = sphere_material(0).bsdf;
    REQUIRE(m0.size() == 2);
    CHECK(m0.lobe(0).type == LobeType::Mirror);
    CHECK(m0.lobe(0).fresnel.eta.b == Approx(1.442f));
    CHECK(m0.lobe(0).color.r == Approx(0.75f));
    CHECK(m0.lobe(1).color.g == Approx(0.25f * 0.25f));
    CHECK(sphere_material(1).bsdf.lobe(0).color.b == Approx(0.375f));
    // coateddiffuse: one layered lobe with pbrt-v4's parameters (smooth coat at roughness 0).
    const Bsdf& coat = sphere_material(2).bsdf;
    REQUIRE(coat.size() == 1);
    CHECK(coat.lobe(0).type == LobeType::Coated);
    CHECK(coat.lobe(0).coat.base == CoatBase::Diffuse);
    CHECK(coat.lobe(0).color.r == Approx(0.5f));
    CHECK(coat.lobe(0).coat.coat_smooth);
    CHECK(coat.lobe(0).coat.ior == Approx(1.5f));
    CHECK(coat.lobe(0).coat.thickness == Approx(0.1f));
    CHECK(coat.lobe(0).coat.albedo.b == Approx(0.4f));
    CHECK(coat.lobe(0).coat.g == Approx(0.5f));
    CHECK(coat.lobe(0).coat.max_depth == 7);
    // coatedconductor: the conductor's index relative to the coat's, roughness remapped
    // (alpha = sqrt(roughness)).
    const Lobe& cc = sphere_material(4).bsdf.lobe(0);
    CHECK(cc.type == LobeType::Coated);
    CHECK(cc.coat.base == CoatBase::Conductor);
    CHECK(cc.coat.ior == Approx(1.6f));
    CHECK(!cc.coat.coat_smooth);
    CHECK(cc.coat.coat.alpha == Approx(0.3f));
    CHECK(cc.fresnel.eta.b == Approx(1.442f / 1.6f).epsilon(0.01));
    CHECK(!cc.coat.base_smooth);
    CHECK(cc.dist.alpha == Approx(0.2f));
    CHECK(cc.dist.alpha_y == Approx(0.4f));
    CHECK(sphere_material(3).ior == Approx(1.5168f));
    REQUIRE(s.lights.points.size() == 1);
    CHECK(s.lights.points[0].intensity.b == Approx(3.f));
    CHECK(s.lights.points[0].position.y == Approx(4.f));
    REQUIRE(s.lights.spots.size() == 1);
    // power 100 over pbrt's spot solid angle, colour of luminance 1.
    const SpotLight& spot = s.lights.spots[0];
    const float k_e =
        2.f * kPi * ((1.f - spot.cos_inner) + 0.5f * (spot.cos_inner - spot.cos_outer));
    CHECK(spot.intensity.luminance() == Approx(100.f / k_e).epsilon(0.03));
    CHECK(spot.intensity.r > spot.intensity.b);  // 3000 K is red
    REQUIRE(s.lights.directionals.size() == 1);
    CHECK(s.lights.directionals[0].direction.y == Approx(-1.f));
    CHECK(s.lights.directionals[0].radiance.g == Approx(3.f));
    CHECK(s.renderer.text("type") == "sppm");
    CHECK(s.renderer.text("spp") == "7");
}

TEST_CASE("pbrt-v4: infinite lights, constant and equal-area image", "[pbrt][env][fast]") {
    // Constant: L times scale, or scaled to an illuminance (pi L for a constant sky).
    const Scene c = world("", R"(LightSource "infinite" "rgb L" [0.5 1 2] "float scale" 2)");
    REQUIRE(c.environment);
    CHECK(c.environment->layers()[0].mapping == EnvMapping::Constant);
    CHECK(c.environment->Le({}, {0, 1, 0}).b == Approx(4.f));
    const Scene e = world("", R"(LightSource "infinite" "float illuminance" [3.14159265])");
    CHECK(e.environment->Le({}, {1, 0, 0}).g == Approx(1.f));
    // An image in the light's frame: pbrt's +z pole, here rotated to world +y. The map is
    // bright in its upper half (the square's centre is the pole) and dark below.
    test::TempDir dir;
    Film map(32, 32);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            const Vec3 w = equal_area_square_to_sphere({(x + 0.5f) / 32.f, (y + 0.5f) / 32.f});
            map.pixels[std::size_t(y * 32 + x)] = w.z > 0.f ? RGB{2.f} : RGB{0.25f};
        }
    write_exr(dir.file("sky.exr"), map);
    const Scene i = import_text(R"(WorldBegin
        AttributeBegin Rotate -90 1 0 0
        LightSource "infinite" "string filename" "sky.exr" "float illuminance" [10]
        AttributeEnd
        Shape "sphere")",
                                dir.path().string());
    REQUIRE(i.environment);
    CHECK(i.environment->layers()[0].mapping == EnvMapping::EqualArea);
    // Scaled so that a surface facing the pole gets illuminance 10: the upper hemisphere of
    // radiance 2 x k gives 2 pi k, about (texels straddle the horizon).
    const float k = i.environment->Le({}, {0, 1, 0}).r / 2.f;
    CHECK(2.f * kPi * k == Approx(10.f).epsilon(0.05));
    CHECK(i.environment->Le({}, {0, -1, 0}).r == Approx(0.25f * k));
    CHECK(i.environment->Le({}, {0, 0, 1}).r > 0.f);
    const std::string summary = i.summary();
    CHECK(summary.find("environment equalarea 32x32") != std::string::npos);
    // A non-square map is not an equal-area map.
    write_exr(dir.file("wide.exr"), Film(8, 4));
    try {
        import_text(
            "WorldBegin\nLightSource \"infinite\" \"string filename\" \"wide.exr\"\n"
            "Shape \"sphere\"",
            dir.path().string());
        FAIL("a non-square map was accepted");
    } catch (const InputError& err) {
        CHECK(std::string(err.what()).find("test.pbrt:2: environment map 'wide.exr'") !=
              std::string::npos);
        CHECK(std::string(err.what()).find("must be square") != std::string::npos);
    }
}

TEST_CASE("pbrt-v4: spectra reduce to RGB", "[pbrt][fast]") {
    const RGB d65 = pbrt::blackbody_rgb(6504.f);
    CHECK(d65.luminance() == Approx(1.f).epsilon(0.02));
    CHECK(d65.r == Approx(1.f).margin(0.08));
    CHECK(d65.b == Approx(1.f).margin(0.08));
    const RGB flat = pbrt::sampled_spectrum_rgb({400, 0.3f, 700, 0.3f}, false);
    CHECK(flat.r == Approx(0.3f).epsilon(1e-3));
    CHECK(flat.b == Approx(0.3f).epsilon(1e-3));
    const RGB red = pbrt::sampled_spectrum_rgb({400, 0.f, 599, 0.f, 600, 1.f, 700, 1.f}, false);
    CHECK(red.r > 4.f * red.b);
    CHECK(pbrt::named_spectrum_rgb("metal-Cu-k").has_value());
    CHECK(!pbrt::named_spectrum_rgb("metal-Xx-k").has_value());
}

TEST_CASE("pbrt-v4: spectra from .spd files, bad ones at their line", "[pbrt][fast]") {
    // pbrt-v4-scenes' gold killeroos give a conductor's eta and k as files of wavelength-value
    // pairs, resolved against the main file's directory.
    test::TempDir dir;
    std::ofstream(dir.file("flat.spd")) << "# a flat spectrum\n300 0.5\n550 0.5 # mid\n800 0.5\n";
    std::ofstream(dir.file("rising.spd")) << "400 1\n500 2\n600 3\n700 4\n";
    std::ofstream(dir.file("odd.spd")) << "300 0.5\n550\n";
    std::ofstream(dir.file("word.spd")) << "300 0.5\n550 x\n";
    auto scene_with = [&](const std::string& eta) {
        return import_text(
            "Camera \"perspective\"\nWorldBegin\nMaterial \"conductor\" "
            "\"spectrum eta\" \"" +
                eta + "\" \"spectrum k\" \"flat.spd\"\nShape \"sphere\"\n",
            dir.path().string());
    };
    const Scene flat = scene_with("flat.spd");
    const Fresnel& f = flat.materials.back().bsdf.lobe(0).fresnel;
    CHECK(f.kind == FresnelKind::Conductor);
    CHECK(f.eta.r == Approx(0.5f).epsilon(1e-3));
    CHECK(f.eta.b == Approx(0.5f).epsilon(1e-3));
    CHECK(f.k.g == Approx(0.5f).epsilon(1e-3));
    // The same as the pairs given inline.
    const RGB rising = scene_with("rising.spd").materials.back().bsdf.lobe(0).fresnel.eta;
    const RGB inline_pairs = pbrt::sampled_spectrum_rgb({400, 1, 500, 2, 600, 3, 700, 4}, false);
    CHECK(rising.r == inline_pairs.r);
    CHECK(rising.b == inline_pairs.b);
    CHECK(rising.r > rising.b);
    auto error = [&](const std::string& eta) -> std::string {
        try {
            scene_with(eta);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    CHECK_THAT(error("missing.spd"),
               Catch::Contains("test.pbrt:3: parameter 'spectrum eta': unknown named spectrum "
                               "'missing.spd'") &&
                   Catch::Contains("no spectrum file of that name"));
    CHECK_THAT(error("odd.spd"), Catch::Contains("odd.spd: a spectrum file holds "
                                                 "wavelength-value pairs, and this has 3"));
    CHECK_THAT(error("word.spd"), Catch::Contains("word.spd:2: 'x' is not a number"));
}

TEST_CASE("pbrt-v4: what foton leaves out is a warning at its line", "[pbrt][fast]") {
    const Scene s = world(R"(PixelFilter "mitchell" "float foo" 1
        Sampler "pmj02bn" "integer pixelsamples" 8
        Integrator "volpath" "integer maxdepth" 3 "float foo" 1)",
                          R"(Material "diffuse" "float sigma" [ 0 ]
        Shape "sphere")");
    auto has = [&](const std::string& text) {
        for (const std::string& w : s.warnings)
            if (w.find(text) != std::string::npos) return true;
        return false;
    };
    CHECK(has("test.pbrt:1: unsupported parameter 'float foo' of PixelFilter \"mitchell\""));
    CHECK(s.film.filter.type() == FilterType::Mitchell);
    CHECK(has("test.pbrt:2: Sampler \"pmj02bn\""));
    CHECK(has("test.pbrt:3: unsupported parameter 'float foo' of Integrator \"volpath\""));
    CHECK(has("test.pbrt:5: unsupported parameter 'float sigma' of Material \"diffuse\""));
    CHECK(s.renderer.text("spp") == "8");
    CHECK(s.renderer.text("max_depth") == "3");
    CHECK(s.renderer.text("type") == "volpath");
    // pbrt-v4's bdpt is foton's bdpt, not the path tracer.
    const Scene b = world(R"(Integrator "bdpt" "integer maxdepth" 4 "bool visualizeweights" true)",
                          R"(Shape "sphere")");
    CHECK(b.renderer.text("type") == "bdpt");
    CHECK(b.renderer.text("max_depth") == "4");
    bool said = false;
    for (const std::string& w : b.warnings)
        said |= w.find("visualizeweights ignored") != std::string::npos;
    CHECK(said);
    // pbrt-v4's mlt is foton's over bdpt paths (its difference said), with its parameters.
    const Scene m = world(R"(Integrator "mlt" "integer maxdepth" 6 "integer bootstrapsamples" 5000
        "integer chains" 300 "integer mutationsperpixel" 12 "float largestepprobability" 0.25
        "float sigma" 0.02)",
                          R"(Shape "sphere")");
    CHECK(m.renderer.text("type") == "mlt");
    CHECK(m.renderer.text("max_depth") == "6");
    CHECK(m.renderer.text("mlt_bootstrap") == "5000");
    CHECK(m.renderer.text("mlt_chains") == "300");
    CHECK(m.renderer.text("mlt_paths") == "bdpt");
    CHECK(m.renderer.text("spp") == "12");
    CHECK(std::stof(m.renderer.text("large_step")) == Approx(0.25f));
    CHECK(std::stof(m.renderer.text("mlt_sigma")) == Approx(0.02f));
    bool mlt_said = false;
    for (const std::string& w : m.warnings)
        mlt_said |= w.find("one strategy at a time") != std::string::npos;
    CHECK(mlt_said);
}

TEST_CASE("pbrt-v4: the sensor's ISO and exposure time scale every emitter", "[pbrt][fast]") {
    // imaging ratio = (shutterclose - shutteropen) x iso / 100 = 0.5 x 400 / 100 = 2.
    const std::string lights = R"(LightSource "point" "rgb I" [1 2 3]
        AttributeBegin AreaLightSource "diffuse" "rgb L" [4 5 6]
        Shape "sphere" "float radius" 0.5 AttributeEnd)";
    const Scene base = world("", lights);
    const Scene bright = world(R"(Film "rgb" "float iso" 400
        Camera "perspective" "float shutteropen" 0.25 "float shutterclose" 0.75)",
                               lights);
    REQUIRE(bright.lights.points.size() == 1);
    CHECK(bright.lights.points[0].intensity.g == Approx(2.f * base.lights.points[0].intensity.g));
    auto emission = [](const Scene& s) {
        for (const Object& o : s.objects)
            if (o.kind == ObjectKind::Sphere) return s.materials[o.material].emission;
        return RGB{0.f};
    };
    CHECK(emission(base).b == Approx(6.f));
    CHECK(emission(bright).b == Approx(12.f));
    bool quiet = true;  // the shutter is read, not ignored
    for (const std::string& w : bright.warnings) quiet &= w.find("shutter") == std::string::npos;
    CHECK(quiet);
    const Scene wb = world(R"(Film "rgb" "float whitebalance" 6500)", "");
    bool said = false;
    for (const std::string& w : wb.warnings)
        said |= w.find("whitebalance ignored") != std::string::npos;
    CHECK(said);
    CHECK_THAT(error_of(R"(Film "rgb" "float iso" 0
        WorldBegin Shape "sphere")"),
               Catch::Contains("iso must be positive"));
}

TEST_CASE("pbrt-v4: the low-discrepancy samplers are foton's", "[pbrt][fast]") {
    const std::vector<std::tuple<std::string, std::string, bool>> cases = {
        {"\"sobol\"", "sobol", false},
        {"\"zsobol\"", "zsobol", false},
        {"\"halton\"", "halton", false},
        {"\"sobol\" \"string randomization\" \"owen\"", "sobol", false},
        {"\"halton\" \"string randomization\" \"permutedigits\"", "halton", false},
        {"\"paddedsobol\"", "sobol", true},
        {"\"zsobol\" \"string randomization\" \"none\"", "zsobol", true},
        {"\"pmj02bn\"", "jittered", true},
        {"\"independent\"", "random", false},
        {"\"stratified\" \"bool jitter\" false", "regular", false}};
    for (const auto& [decl, ours, warned] : cases) {
        const Scene s =
            world("Sampler " + decl + " \"integer pixelsamples\" 4", "Shape \"sphere\"");
        INFO(decl);
        CHECK(s.renderer.text("sampler") == ours);
        bool said = false;
        for (const std::string& w : s.warnings) said |= w.find("Sampler") != std::string::npos;
        CHECK(said == warned);
    }
}

TEST_CASE("pbrt-v4: the path integrator's lightsampler is foton's light_selection",
          "[pbrt][lights][fast]") {
    // pbrt-v4's default is its BVH light sampler; exhaustive is rendered with the tree.
    const std::pair<std::string, std::string> cases[] = {
        {"", "bvh"},
        {"\"string lightsampler\" \"bvh\"", "bvh"},
        {"\"string lightsampler\" \"power\"", "power"},
        {"\"string lightsampler\" \"uniform\"", "uniform"},
        {"\"string lightsampler\" \"exhaustive\"", "bvh"}};
    for (const auto& [param, selection] : cases) {
        const Scene s = world("Integrator \"path\" " + param, R"(Shape "sphere")");
        INFO(param);
        CHECK(s.renderer.text("light_selection") == selection);
        CHECK(render_settings(s).light_selection == (selection == "bvh" ? LightSelection::Bvh
                                                     : selection == "power"
                                                         ? LightSelection::Power
                                                         : LightSelection::Uniform));
    }
    const std::string bad = error_of(
        "Integrator \"path\" \"string lightsampler\" \"nearest\"\nWorldBegin\nShape \"sphere\"");
    CHECK(bad.find("test.pbrt:1: lightsampler \"nearest\"") != std::string::npos);
}

TEST_CASE("pbrt-v4: bad input is an error at its file and line", "[pbrt][fast]") {
    const std::string shape = "\nShape \"sphere\"\n";
    const std::pair<std::string, std::string> cases[] = {
        {"WorldBegin\nFoo 1", "test.pbrt:2: unknown directive 'Foo'"},
        {"WorldBegin\nShape \"sphere\" \"float radius [ 1 ]", "test.pbrt:2: unterminated string"},
        {"WorldBegin\nShape \"sphere\" \"radius\" [ 1 ]", "test.pbrt:2: malformed parameter"},
        {"WorldBegin\nShape \"sphere\" \"float radius\" [ 1 ", "missing ']'"},
        {"WorldBegin\nShape \"sphere\" \"float radius\" [ nan ]",
         "test.pbrt:2: parameter 'radius': 'nan' is not a number"},
        {"WorldBegin\nShape \"sphere\" \"integer radius\" [ 1.5 ]", "is not an integer"},
        {"WorldBegin\nShape \"sphere\" \"float radius\" [ -1 ]", "test.pbrt:2: sphere radius"},
        {"WorldBegin\nShape \"cone\"", "test.pbrt:2: unsupported shape 'cone'"},
        {"WorldBegin\nShape \"curve\" \"point3 P\" [0 0 0 1 0 0 2 0 0]",
         "test.pbrt:2: Shape \"curve\": a degree 3 Bézier curve needs 3 k + 1 points, not 3"},
        {"WorldBegin\nShape \"curve\" \"string type\" \"ribbon\" \"point3 P\" [0 0 0 1 0 0 "
         "2 0 0 3 0 0]",
         "test.pbrt:2: Shape \"curve\": a ribbon needs \"normal N\""},
        {"WorldBegin\nShape \"curve\" \"string type\" \"round\" \"point3 P\" [0 0 0 1 0 0 "
         "2 0 0 3 0 0]",
         "test.pbrt:2: Shape \"curve\": type 'round'"},
        {"WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] "
         "\"integer indices\" [0 1 3]",
         "test.pbrt:2: Shape \"trianglemesh\": index 3 outside the 3 points"},
        {"WorldBegin\nInclude \"missing.pbrt\"",
         "test.pbrt:2: Include 'missing.pbrt': file not found"},
        {"WorldBegin\nMaterial \"measured\"" + shape,
         "test.pbrt:2: Material \"measured\" needs a \"string filename\""},
        {"WorldBegin\nMaterial \"measured\" \"string filename\" \"gold.bsdf\"" + shape,
         "test.pbrt:2: Material \"measured\" file 'gold.bsdf': file not found"},
        {"WorldBegin\nMaterial \"hair\" \"float eta\" [-1]" + shape,
         "test.pbrt:2: Material \"hair\": eta must be positive"},
        {"WorldBegin\nNamedMaterial \"x\"" + shape, "unknown named material 'x'"},
        {"WorldBegin\nLightSource \"goniometric\"" + shape, "unsupported light 'goniometric'"},
        {"WorldBegin\nAttributeEnd" + shape, "test.pbrt:2: AttributeEnd without"},
        {"WorldBegin\nAttributeBegin" + shape, "without its end"},
        {"WorldBegin\nObjectInstance \"x\"" + shape, "unknown object 'x'"},
        {"WorldBegin\nScale 0 1 1" + shape, "test.pbrt:2: Scale: the transform is singular"},
        {"WorldBegin\nScale 1 2 1" + shape, "test.pbrt:3: a sphere takes only uniform scaling"},
        {"WorldBegin\nTransform [1 0 0 0 0 1 0 0 0 0 1 1 0 0 0 1]" + shape, "projective"},
        {"WorldBegin\nCamera \"perspective\"" + shape, "test.pbrt:2: Camera belongs before"},
        {"Camera \"realistic\"\nWorldBegin" + shape, "test.pbrt:1: unsupported camera"},
        {"Film \"rgb\" \"integer xresolution\" [ 100000 ]\nWorldBegin" + shape, "test.pbrt:1:"},
        {"WorldBegin\nMakeNamedMedium \"fog\" \"string type\" \"cloud\"" + shape,
         "test.pbrt:2: MakeNamedMedium \"fog\": medium type 'cloud' is not supported yet"},
        {"WorldBegin\nMakeNamedMedium \"fog\" \"string type\" \"uniformgrid\"" + shape,
         "test.pbrt:2: MakeNamedMedium \"fog\": \"density\" has 0 values, nx * ny * nz is 1"},
        {"WorldBegin\nMakeNamedMedium \"fog\"" + shape, "needs \"string type\""},
        {"WorldBegin\nMakeNamedMedium \"f\" \"string type\" \"homogeneous\" \"float g\" 1" + shape,
         "test.pbrt:2: MakeNamedMedium \"f\": g must be in (-1, 1)"},
        {"WorldBegin\nMediumInterface \"fog\" \"\"" + shape,
         "test.pbrt:2: unknown medium 'fog' (define it with MakeNamedMedium first)"},
        {"WorldBegin\nLightSource \"infinite\" \"string filename\" \"sky.exr\"" + shape,
         "test.pbrt:2: environment map 'sky.exr': file not found"},
        {"WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1] \"string filename\" \"a.exr\"" +
             shape,
         "test.pbrt:2: LightSource \"infinite\": give \"L\" or \"filename\", not both"},
        {"WorldBegin\nLightSource \"infinite\" \"point3 portal\" [0 0 0 1 0 0 1 1 0]" + shape,
         "test.pbrt:2: LightSource \"infinite\": a portal has 4 corners, not 3"},
        {"WorldBegin\nLightSource \"infinite\" \"point3 portal\" [0 0 0 1 0 0 1 2 0 0 1 0]" + shape,
         "test.pbrt:2: LightSource \"infinite\": a portal must be a rectangle"},
        {"WorldBegin\nShape \"sphere\" \"spectrum reflectance\" \"metal-Zz-eta\"\n"
         "Material \"diffuse\" \"spectrum reflectance\" \"metal-Zz-eta\"" +
             shape,
         "test.pbrt:3: parameter 'spectrum reflectance': unknown named spectrum"},
        {"WorldBegin\nMaterial \"diffuse\" \"texture reflectance\" \"nope\"" + shape,
         "test.pbrt:2: unknown spectrum texture 'nope'"},
        {"WorldBegin", "the scene has no shapes"},
        {"WorldBegin\n@", "test.pbrt:2: unexpected character '@'"},
    };
    for (const auto& [text, want] : cases) {
        INFO(text);
        const std::string got = error_of(text);
        INFO("got: " << got);
        CHECK(got.find(want) != std::string::npos);
    }
}

TEST_CASE("pbrt-v4: Include resolves against the scene's directory, plymesh reads PLY",
          "[pbrt][fast]") {
    test::TempDir dir;
    {
        std::ofstream(dir.file("geometry.pbrt")) << "Shape \"plymesh\" \"string filename\" "
                                                    "\"quad.ply\"\n";
        std::ofstream(dir.file("quad.ply"))
            << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
               "property float z\nproperty float u\nproperty float v\nelement face 1\n"
               "property list uchar int vertex_indices\nend_header\n"
               "0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n4 0 1 2 3\n";
        std::ofstream(dir.file("main.pbrt")) << "WorldBegin\nTranslate 0 0 2\n"
                                                "Include \"geometry.pbrt\"\n";
    }
    const Scene s = load_scene(dir.file("main.pbrt"));
    REQUIRE(s.meshes.size() == 1);
    CHECK(s.meshes[0].num_triangles() == 2);
    CHECK(s.meshes[0].uvs.size() == 8);
    CHECK(s.meshes[0].vertex(2).z == Approx(2.f));
    CHECK(s.source == dir.file("main.pbrt"));
}

TEST_CASE("textures: bilinear image lookups and sRGB decoding", "[texture][fast]") {
    test::TempDir dir;
    // A 2 x 2 binary PPM: red, green / blue, grey 128 (sRGB).
    const std::string path = dir.file("t.ppm");
    {
        std::ofstream f(path, std::ios::binary);
        f << "P6\n2 2\n255\n";
        const unsigned char px[] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 128, 128, 128};
        f.write(reinterpret_cast<const char*>(px), sizeof px);
    }
    const TextureImage img = load_texture_image(path);
    REQUIRE(img.width == 2);
    const float grey = 0.2158605f;  // sRGB 128/255 decoded
    // Texel centres give the texels; v = 0 is the bottom row.
    CHECK(img.bilinear({0.25f, 0.75f}).r == Approx(1.f));
    CHECK(img.bilinear({0.75f, 0.75f}).g == Approx(1.f));
    CHECK(img.bilinear({0.25f, 0.25f}).b == Approx(1.f));
    CHECK(img.bilinear({0.75f, 0.25f}).g == Approx(grey).epsilon(1e-4));
    // Half-way between red and green; repeating across the edge.
    const RGB mid = img.bilinear({0.5f, 0.75f});
    CHECK(mid.r == Approx(0.5f));
    CHECK(mid.g == Approx(0.5f));
    CHECK(img.bilinear({1.25f, -0.25f}).r == Approx(img.bilinear({0.25f, 0.75f}).r));
    CHECK(load_texture_image(path, true).bilinear({0.75f, 0.25f}).g == Approx(128.f / 255.f));
    // Bad files name themselves.
    std::ofstream(dir.file("bad.png")) << "not an image";
    CHECK_THROWS_WITH(load_texture_image(dir.file("bad.png")),
                      Catch::Contains(dir.file("bad.png") + ": not a readable image"));
}

TEST_CASE("textures: a textured quad renders the texture's colours", "[texture][pbrt]") {
    test::TempDir dir;
    {
        std::ofstream f(dir.file("t.ppm"), std::ios::binary);
        f << "P6\n2 2\n255\n";
        const unsigned char px[] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 128, 128, 128};
        f.write(reinterpret_cast<const char*>(px), sizeof px);
        // Irradiance pi on a Lambertian quad: its radiance is its albedo, texel by texel.
        std::ofstream(dir.file("quad.pbrt"))
            << head_on_unit_square(64, "PixelFilter \"box\"\n") +
                   "Texture \"img\" \"spectrum\" \"imagemap\" \"string filename\" \"t.ppm\"\n"
                   "Texture \"checks\" \"spectrum\" \"checkerboard\" \"float uscale\" 4 "
                   "\"float vscale\" 4 \"rgb tex1\" [0.8 0.8 0.8] \"rgb tex2\" [0.1 0.2 0.3]\n"
                   "MakeNamedMaterial \"a\" \"string type\" \"diffuse\" \"texture reflectance\" "
                   "\"img\"\n"
                   "MakeNamedMaterial \"b\" \"string type\" \"diffuse\" \"texture reflectance\" "
                   "\"checks\"\n"
                   "MakeNamedMaterial \"c\" \"string type\" \"diffuse\"\n"
                   "Material \"mix\" \"string materials\" [\"c\" \"a\"] \"float amount\" 1\n"
                   "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 1 1 0 0 1 0] "
                   "\"point2 uv\" [0 0 1 0 1 1 0 1] \"integer indices\" [0 1 2 0 2 3]\n"
                   "AttributeBegin Translate 0 0 -1 NamedMaterial \"b\"\n"
                   "Shape \"trianglemesh\" \"point3 P\" [-1 -1 0 2 -1 0 2 2 0 -1 2 0] "
                   "\"point2 uv\" [0 0 1 0 1 1 0 1] \"integer indices\" [0 1 2 0 2 3]\n"
                   "AttributeEnd\n"
                   "Material \"mix\" \"string materials\" [\"a\" \"b\"] \"float amount\" 0.5\n";
    }
    CHECK_THROWS_WITH(load_scene(dir.file("quad.pbrt")),
                      Catch::Contains("quad.pbrt:19: a mix of two differently textured"));
    // Without the last line: the quad in front (the checkerboard plane behind it is hidden).
    {
        std::ifstream in(dir.file("quad.pbrt"));
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        text.erase(text.rfind("Material"));
        std::ofstream(dir.file("quad.pbrt")) << text;
    }
    Scene s = load_scene(dir.file("quad.pbrt"));
    // The checkerboard: 4 x 4 cells over the unit square.
    CHECK(s.textures[1].eval(s.texture_images, {0.1f, 0.1f}).r == Approx(0.8f));
    CHECK(s.textures[1].eval(s.texture_images, {0.3f, 0.1f}).b == Approx(0.3f));
    CHECK(s.texture_images.size() == 1);
    CHECK(s.textures.size() == 2);
    TestScene ts(std::move(s));
    const auto acc = make_intersector(ts, ts.accel);
    RenderOptions opt = ts.render.run;
    opt.spp = 16;
    const Film f = render(ts, ts.render, *acc, opt).film;
    auto px = [&](int x, int y) { return f.pixels[std::size_t(y) * 64 + std::size_t(x)]; };
    // Image rows run down, v up: the top-left texel (red) is at the image's top left.
    CHECK(px(16, 16).r > 0.9f);
    CHECK(px(16, 16).g < 0.1f);
    // Every pixel: the bilinear texture averaged over the pixel's square (8 x 8 points).
    const TextureImage& img = ts.texture_images[0];
    double worst = 0.0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            RGB want{0.f};
            for (int j = 0; j < 8; ++j)
                for (int i = 0; i < 8; ++i)
                    want += img.bilinear({(float(x) + (float(i) + 0.5f) / 8.f) / 64.f,
                                          1.f - (float(y) + (float(j) + 0.5f) / 8.f) / 64.f}) *
                            (1.f / 64.f);
            const RGB got = px(x, y);
            worst =
                std::max({worst, double(std::fabs(got.r - want.r)),
                          double(std::fabs(got.g - want.g)), double(std::fabs(got.b - want.b))});
        }
    INFO("worst pixel difference " << worst);
    CHECK(worst < 0.01);
}

TEST_CASE("pbrt-v4: homogeneous media, MediumInterface, the camera's medium, interface",
          "[pbrt][media][fast]") {
    const Scene s = import_text(R"(LookAt 0 0 5  0 0 0  0 1 0
MakeNamedMedium "fog" "string type" "homogeneous" "rgb sigma_a" [0.1 0.2 0.3]
    "rgb sigma_s" [1 2 3] "float scale" 2 "float g" 0.4 "rgb Le" [0.5 0.5 0.5] "float Lescale" 2
MediumInterface "" "fog"
Camera "perspective"
Film "rgb" "float iso" 200
WorldBegin
AttributeBegin
  MediumInterface "fog" ""
  Material "interface"
  Shape "sphere" "float radius" 2
AttributeEnd
AttributeBegin
  Material "dielectric"
  Shape "sphere" "float radius" 0.5
AttributeEnd
)");
    REQUIRE(s.media.size() == 1);
    const Medium& m = s.media[0];
    CHECK(m.sigma_a.b == Approx(0.6f));
    CHECK(m.sigma_s.g == Approx(4.f));
    CHECK(m.g == Approx(0.4f));
    CHECK(m.Le.r == Approx(0.5f * 2.f * 2.f));  // Lescale, and the film's ISO 200
    CHECK(s.camera_medium == 0);
    REQUIRE(s.objects.size() == 2);
    CHECK(s.objects[0].media.inside == 0);
    CHECK(s.objects[0].media.outside == kNoMedium);
    CHECK(s.material_of(0).is_interface);
    CHECK(s.material_of(0).bsdf.empty());
    // Outside the AttributeBegin block the interface is the one before it, given before the
    // camera (pbrt-v4 keeps it through WorldBegin): vacuum inside, fog outside.
    CHECK(s.objects[1].media.inside == kNoMedium);
    CHECK(s.objects[1].media.outside == 0);
    CHECK(s.volumetric());
    CHECK(s.volumetric_line == 2);
    // No Integrator: pbrt-v4's default, volpath.
    CHECK(s.renderer.text("type") == "volpath");
}

TEST_CASE("pbrt-v4: an absorbing sphere imported renders exp(-sigma_a chord)",
          "[pbrt][media][render]") {
    // A glass-free absorbing ball under a white sky: the centre pixel's transmittance is
    // exp(-2 sigma_a r), the corners see the sky.
    Scene s = import_text(R"(LookAt 0 0 10  0 0 0  0 1 0
Camera "orthographic" "float screenwindow" [-0.05 0.05 -0.05 0.05]
Film "rgb" "integer xresolution" 4 "integer yresolution" 4
Integrator "volpath" "integer maxdepth" 10
WorldBegin
LightSource "infinite" "rgb L" [1 1 1]
MakeNamedMedium "ink" "string type" "homogeneous" "rgb sigma_a" [0.2 0.5 1] "rgb sigma_s" [0 0 0]
MediumInterface "ink" ""
Material "interface"
Shape "sphere" "float radius" 1
)");
    const Film f = render_at(std::move(s), 4, 16);
    RGB mean{0.f};
    for (const RGB& p : f.pixels) mean += p * (1.f / float(f.pixels.size()));
    // The window is 0.1 wide: every ray's chord is within 0.3 % of 2.
    CHECK(mean.r == Approx(std::exp(-0.4f)).epsilon(0.01));
    CHECK(mean.g == Approx(std::exp(-1.f)).epsilon(0.01));
    CHECK(mean.b == Approx(std::exp(-2.f)).epsilon(0.01));
}

TEST_CASE("pbrt-v4: a mix's texture amount weighs its two materials per hit", "[pbrt][texture]") {
    test::TempDir dir;
    // Irradiance pi on a unit quad seen head-on: each pixel's radiance is its albedo. The
    // amount is a float checkerboard of 0 and 0.25 in 2 x 2 cells over the quad.
    std::ofstream(dir.file("mix.pbrt"))
        << head_on_unit_square(64) +
               "Texture \"amount\" \"float\" \"checkerboard\" \"float uscale\" 2 \"float vscale\" "
               "2 "
               "\"float tex1\" 0 \"float tex2\" 0.25\n"
               "MakeNamedMaterial \"red\" \"string type\" \"diffuse\" \"rgb reflectance\" [0.8 0.1 "
               "0.1]\n"
               "MakeNamedMaterial \"blue\" \"string type\" \"coateddiffuse\" \"rgb reflectance\" "
               "[0.1 0.1 0.8] \"float roughness\" 0.3\n"
               "Material \"mix\" \"string materials\" [\"red\" \"blue\"] \"texture amount\" "
               "\"amount\"\n"
               "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 1 1 0 0 1 0] "
               "\"point2 uv\" [0 0 1 0 1 1 0 1] \"integer indices\" [0 1 2 0 2 3]\n";
    const Scene s = load_scene(dir.file("mix.pbrt"));
    const Material& m = s.materials[s.objects.at(0).material];
    REQUIRE(m.bsdf.size() == 2);
    REQUIRE(m.num_float_params == 2);
    std::optional<Material> scratch;
    // Cell (0, 0): amount 0, the red Lambert alone; cell (1, 0): amount 0.25.
    const Material& a = s.textured(m, {0.25f, 0.25f}, scratch);
    CHECK(a.bsdf.lobe(0).color.r == Approx(0.8f));
    CHECK(a.bsdf.lobe(1).coat.weight == Approx(0.f).margin(1e-6));
    std::optional<Material> scratch2;
    const Material& b = s.textured(m, {0.75f, 0.25f}, scratch2);
    CHECK(b.bsdf.lobe(0).color.r == Approx(0.8f * 0.75f).epsilon(1e-4));
    CHECK(b.bsdf.lobe(1).coat.weight == Approx(0.25f).epsilon(1e-4));
    // Rendered: the red cells are the red albedo; the others three quarters of it and a
    // quarter of the coated blue (whose albedo is below its reflectance's 0.8 in blue).
    TestScene ts(load_scene(dir.file("mix.pbrt")));
    const auto acc = make_intersector(ts, ts.accel);
    RenderOptions opt = ts.render.run;
    opt.spp = 64;
    const Film f = render(ts, ts.render, *acc, opt).film;
    auto px = [&](int x, int y) { return f.pixels[std::size_t(y) * 64 + std::size_t(x)]; };
    // Image rows run down and v up: pixel (16, 48) is in cell (0, 0).
    for (const auto& [x, y] : {std::pair{16, 48}, std::pair{48, 16}}) {
        CHECK(px(x, y).r == Approx(0.8f).epsilon(0.02));
        CHECK(px(x, y).b == Approx(0.1f).epsilon(0.02));
    }
    for (const auto& [x, y] : {std::pair{48, 48}, std::pair{16, 16}}) {
        CHECK(px(x, y).r == Approx(0.6f).margin(0.03));  // 0.75 x 0.8 + a little red of the coat
        CHECK(px(x, y).b > 0.075f + 0.1f);               // a quarter of the blue's albedo added
        CHECK(px(x, y).b < 0.075f + 0.25f * 0.8f + 0.02f);
    }
}

TEST_CASE("pbrt-v4: mix textures lerp their operands, scale textures multiply them",
          "[pbrt][texture][fast]") {
    const Scene s = world("", R"(
        Texture "amount" "float" "checkerboard" "float uscale" 2 "float vscale" 2
            "float tex1" 0.25 "float tex2" 1
        Texture "stripes" "spectrum" "checkerboard" "float uscale" 4 "float vscale" 1
            "rgb tex1" [0 0 1] "rgb tex2" [0 1 0]
        Texture "colour" "spectrum" "mix" "rgb tex1" [1 0 0] "texture tex2" "stripes"
            "texture amount" "amount"
        Texture "bump" "float" "mix" "texture amount" "amount" "float tex1" 0 "float tex2" 0.01
        Texture "still" "spectrum" "mix" "rgb tex1" [1 0 0] "rgb tex2" [0 0 1] "float amount" 0.25
        Texture "dimmed" "spectrum" "scale" "texture tex" "stripes" "texture scale" "amount"
        Texture "tinted" "spectrum" "scale" "rgb tex" [0.5 0.5 0.5] "texture scale" "amount"
        Texture "scaled" "spectrum" "scale" "texture tex" "colour" "float scale" 2
        Material "diffuse" "texture reflectance" "scaled" "texture displacement" "bump"
        Shape "sphere"
        Material "diffuse" "texture reflectance" "still"
        Shape "sphere"
        Material "diffuse" "texture reflectance" "dimmed"
        Shape "sphere"
        Material "diffuse" "texture reflectance" "tinted"
        Shape "sphere"
    )");
    const Material& m = s.materials[s.objects.at(0).material];
    REQUIRE(m.texture >= 0);
    REQUIRE(m.bump >= 0);
    const Texture& colour = s.textures[std::size_t(m.texture)];
    // (0.1, 0.1): amount 0.25, stripes blue; (0.6, 0.1): amount 1, stripes blue; (0.4, 0.1):
    // amount 0.25, stripes green. Times the scale texture's 2.
    const RGB a = colour.eval(s.texture_images, {0.1f, 0.1f});
    CHECK(a.r == Approx(2.f * 0.75f));
    CHECK(a.b == Approx(2.f * 0.25f));
    const RGB b = colour.eval(s.texture_images, {0.6f, 0.1f});
    CHECK(b.r == Approx(0.f).margin(1e-6));
    CHECK(b.b == Approx(2.f));
    CHECK(colour.eval(s.texture_images, {0.4f, 0.1f}).g == Approx(2.f * 0.25f));
    const Texture& bump = s.textures[std::size_t(m.bump)];
    CHECK(bump.eval_float(s.texture_images, {0.1f, 0.1f}) == Approx(0.0025f));
    CHECK(bump.eval_float(s.texture_images, {0.6f, 0.1f}) == Approx(0.01f));
    // Constant operands fold into a constant reflectance.
    const Material& still = s.materials[s.objects.at(1).material];
    CHECK(still.texture < 0);
    CHECK(still.bsdf.lobe(0).color.r == Approx(0.75f));
    CHECK(still.bsdf.lobe(0).color.b == Approx(0.25f));
    // A scale texture whose scale varies: the product at each point (varying x varying and
    // constant x varying).
    const Texture& dimmed = s.textures[std::size_t(s.materials[s.objects.at(2).material].texture)];
    CHECK(dimmed.eval(s.texture_images, {0.1f, 0.1f}).b == Approx(0.25f));
    CHECK(dimmed.eval(s.texture_images, {0.4f, 0.1f}).g == Approx(0.25f));
    CHECK(dimmed.eval(s.texture_images, {0.6f, 0.1f}).b == Approx(1.f));
    const Texture& tinted = s.textures[std::size_t(s.materials[s.objects.at(3).material].texture)];
    CHECK(tinted.eval(s.texture_images, {0.1f, 0.1f}).r == Approx(0.125f));
    CHECK(tinted.eval(s.texture_images, {0.6f, 0.1f}).r == Approx(0.5f));
}

TEST_CASE("pbrt-v4: spherical, cylindrical and planar mappings and directionmix textures",
          "[pbrt][texture][fast]") {
    const Scene s = world("", R"(
        AttributeBegin
          Translate 1 2 3
          Texture "sph" "spectrum" "checkerboard" "string mapping" "spherical"
        AttributeEnd
        AttributeBegin
          Scale 1 1 12
          Texture "cyl" "spectrum" "checkerboard" "string mapping" "cylindrical"
        AttributeEnd
        Texture "plane" "spectrum" "checkerboard" "string mapping" "planar"
            "vector3 v1" [0 0.25 0] "vector3 v2" [0 0 -0.025] "float udelta" 0.55
            "float vdelta" -0.2
        AttributeBegin
          Rotate 90 0 0 1
          Texture "dirmix" "spectrum" "directionmix" "rgb tex1" [1 0 0] "rgb tex2" [0 0 1]
              "vector3 dir" [1 0 0]
        AttributeEnd
        Material "diffuse" "texture reflectance" "sph" Shape "sphere"
        Material "diffuse" "texture reflectance" "cyl" Shape "sphere"
        Material "diffuse" "texture reflectance" "plane" Shape "sphere"
        Material "diffuse" "texture reflectance" "dirmix" Shape "sphere"
    )");
    auto tex = [&](int i) -> const Texture& {
        return s.textures[std::size_t(s.materials[s.objects.at(std::size_t(i)).material].texture)];
    };
    auto st = [](const Texture& t, Vec3 p) { return t.st(TexPoint{{0.f, 0.f}, p, {0, 0, 1}}); };
    // Spherical about (1, 2, 3): theta / pi and phi / 2 pi of the direction from there.
    CHECK(st(tex(0), {1, 2, 4}).x == Approx(0.f).margin(1e-6));
    CHECK(st(tex(0), {2, 2, 3}).x == Approx(0.5f));
    CHECK(st(tex(0), {2, 2, 3}).y == Approx(0.f).margin(1e-6));
    CHECK(st(tex(0), {1, 3, 3}).y == Approx(0.25f));
    // Cylindrical in a space stretched 12 times along z: ((pi + atan2(y, x)) / 2 pi, z / 12).
    CHECK(st(tex(1), {1, 0, 6}).x == Approx(0.5f));
    CHECK(st(tex(1), {1, 0, 6}).y == Approx(0.5f));
    CHECK(st(tex(1), {0, 1, 0}).x == Approx(0.75f));
    // Planar: (udelta + p . v1, vdelta + p . v2).
    CHECK(st(tex(2), {7, 4, 10}).x == Approx(1.55f));
    CHECK(st(tex(2), {7, 4, 10}).y == Approx(-0.45f));
    // directionmix: dir (1, 0, 0) turned 90 degrees about z is y; tex1 where the normal is
    // along it, tex2 across, |n . dir| between.
    const Texture& dm = tex(3);
    CHECK(dm.eval(s.texture_images, TexPoint{{0, 0}, {}, {0, 1, 0}}).r == Approx(1.f));
    CHECK(dm.eval(s.texture_images, TexPoint{{0, 0}, {}, {1, 0, 0}}).b == Approx(1.f));
    const RGB mid = dm.eval(s.texture_images, TexPoint{{0, 0}, {}, {0, -0.6f, 0.8f}});
    CHECK(mid.r == Approx(0.6f));
    CHECK(mid.b == Approx(0.4f));
}

TEST_CASE("pbrt-v4: a planar-mapped texture renders by position, not by uv", "[pbrt][texture]") {
    test::TempDir dir;
    // A unit quad without uv under irradiance pi, seen head-on: each pixel's radiance is its
    // albedo. The checkerboard's cells are 0.5 wide in x and y through the planar mapping.
    std::ofstream(dir.file("planar.pbrt"))
        << head_on_unit_square(32) +
               "Texture \"checks\" \"spectrum\" \"checkerboard\" \"string mapping\" \"planar\" "
               "\"vector3 v1\" [2 0 0] \"vector3 v2\" [0 2 0] \"rgb tex1\" [0.8 0.1 0.1] "
               "\"rgb tex2\" [0.1 0.1 0.8]\n"
               "Material \"diffuse\" \"texture reflectance\" \"checks\"\n"
               "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 1 1 0 0 1 0] "
               "\"integer indices\" [0 1 2 0 2 3]\n";
    TestScene ts(load_scene(dir.file("planar.pbrt")));
    const auto acc = make_intersector(ts, ts.accel);
    RenderOptions opt = ts.render.run;
    opt.spp = 4;
    const Film f = render(ts, ts.render, *acc, opt).film;
    auto px = [&](int x, int y) { return f.pixels[std::size_t(y) * 32 + std::size_t(x)]; };
    // Image rows run down: pixel (8, 24) is at x, y = 0.25 (cell 0, 0: tex1).
    CHECK(px(8, 24).r == Approx(0.8f).epsilon(0.02));
    CHECK(px(24, 24).b == Approx(0.8f).epsilon(0.02));
    CHECK(px(8, 8).b == Approx(0.8f).epsilon(0.02));
    CHECK(px(24, 8).r == Approx(0.8f).epsilon(0.02));
}

TEST_CASE("pbrt-v4: Film maxcomponentvalue and the XML's max_sample_value set the sample clamp",
          "[pbrt][fast]") {
    const Scene s = parse_pbrt_scene(
        "Film \"rgb\" \"float maxcomponentvalue\" 10\nWorldBegin\nShape \"sphere\"\n", "m.pbrt",
        ".");
    CHECK(s.film.max_sample_value == 10.f);
    CHECK(std::isinf(
        parse_pbrt_scene("WorldBegin\nShape \"sphere\"\n", "n.pbrt", ".").film.max_sample_value));
    CHECK_THROWS_WITH(parse_pbrt_scene("Film \"rgb\" \"float maxcomponentvalue\" 0\nWorldBegin\n"
                                       "Shape \"sphere\"\n",
                                       "z.pbrt", "."),
                      Catch::Contains("z.pbrt:1: maxcomponentvalue must be positive"));
    const Scene x = parse_scene(
        R"(<scene><objects><sphere radius="1"><center x="0" y="0" z="0"/><material type="matte"/>
        </sphere></objects>
        <film width="8" height="8" max_sample_value="2"/>
        <camera><eye x="0" y="0" z="5"/><target x="0" y="0" z="0"/></camera></scene>)",
        "m.xml", ".");
    CHECK(x.film.max_sample_value == 2.f);
}

TEST_CASE("pbrt-v4: textures made of textures are refused past 8 levels", "[pbrt][texture][fast]") {
    // Each mix copies the one before as an operand: a chain of 9 is an error at its line.
    std::string text = "WorldBegin\nTexture \"m0\" \"float\" \"checkerboard\"\n";
    for (int i = 1; i <= 9; ++i)
        text += "Texture \"m" + std::to_string(i) + "\" \"float\" \"mix\" \"texture tex1\" \"m" +
                std::to_string(i - 1) + "\" \"float amount\" 0.5\n";
    CHECK_THAT(error_of(text + "Shape \"sphere\"\n"),
               Catch::Contains("test.pbrt:11: textures made of textures nest deeper than 8"));
    // Eight levels are fine.
    text = text.substr(0, text.rfind("Texture \"m9\""));
    CHECK(error_of(text + "Shape \"sphere\"\n").empty());
}

TEST_CASE("pbrt-v4: motion (ActiveTransform) renders the start pose, warned", "[pbrt][fast]") {
    const Scene s = world("",
                          "AttributeBegin\nActiveTransform StartTime\nTranslate 35 0 0\n"
                          "ActiveTransform EndTime\nTranslate 5 0 0\nActiveTransform All\n"
                          "Shape \"sphere\"\nAttributeEnd");
    std::string all;
    for (const std::string& w : s.warnings) all += w + "\n";
    INFO(all);
    CHECK(all.find("test.pbrt:4: ActiveTransform StartTime: motion blur is not supported") !=
          std::string::npos);
    CHECK(all.find("test.pbrt:6: ActiveTransform EndTime") != std::string::npos);
}
