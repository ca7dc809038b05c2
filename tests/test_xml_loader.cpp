// The XML scene format: every element, and every bad-input case of DESIGN.md.
#include <catch2/catch.hpp>
#include <fstream>

#include "engine/core/error.h"
#include "engine/scene/xml_loader.h"
#include "test_util.h"

using namespace foton;

namespace {
const char* kFilmCamera = R"(
  <film width="64" height="48" size="0.01" gamma="2.2"/>
  <camera type="perspective" d="1"><eye x="0" y="0" z="5"/><target x="0" y="0" z="0"/><up x="0" y="1" z="0"/></camera>)";
const char* kSphere = R"(
  <objects><sphere radius="1"><center x="0" y="0" z="0"/><material type="matte"><base_color r="0.5" g="0.5" b="0.5"/></material></sphere></objects>)";

std::string scene_xml(const std::string& body, bool film_camera = true, bool objects = true) {
    return std::string("<scene>") + (film_camera ? kFilmCamera : "") + (objects ? kSphere : "") +
           body + "</scene>";
}

Scene parse(const std::string& xml, const std::string& dir = ".") {
    return parse_scene(xml, "s.xml", dir);
}

void expect_error(const std::string& xml, int line, const std::string& what,
                  const std::string& dir = ".") {
    try {
        // The renderer's settings are checked where they are typed (render_settings).
        const TestScene s = parse(xml, dir);
        FAIL("no error for: " << xml);
    } catch (const InputError& e) {
        INFO(e.what());
        CHECK(e.line() == line);
        CHECK_THAT(e.what(), Catch::Contains(what));
    }
}
}  // namespace

TEST_CASE("XML: the thesis' appendix A elements", "[xml][fast]") {
    const TestScene s = parse(R"(<scene>
  <background r="0.1" g="0.2" b="0.3"/>
  <ambient r="1" g="0.5" b="1" intensity="0.1"/>
  <lights>
    <point intensity="4.0" attenuation="0.5"><color r="1" g="1" b="1"/><position x="-10" y="7.5" z="10"/></point>
    <directional intensity="2"><color r="1" g="0.5" b="0"/><direction x="0" y="-2" z="0"/></directional>
    <spot intensity="3" angle="30" falloff="0.5"><position x="0" y="5" z="0"/><direction x="0" y="-1" z="0"/></spot>
    <area samples="9" sampler="hammersley"><radiance r="15" g="15" b="15"/>
      <corner x="0" y="4" z="0"/><edge1 x="1" y="0" z="0"/><edge2 x="0" y="0" z="2"/></area>
    <area intensity="2"><center x="0" y="4" z="0"/><size x="2" y="1"/><normal x="0" y="-1" z="0"/></area>
  </lights>
  <aggregate type="embree"/>
  <objects>
    <sphere radius="2"><center x="1" y="2" z="3"/>
      <material type="phong" c_ambient="0.1" c_diffuse="0.9" exp="10"><base_color r="0.8" g="0" b="0.8"/><specular_color r="0.5" g="0.5" b="0.5"/></material>
      <transform><scale s="2"/><translate x="1" y="0" z="0"/></transform></sphere>
    <quad><corner x="0" y="0" z="0"/><edge1 x="1" y="0" z="0"/><edge2 x="0" y="0" z="1"/>
      <material type="reflective" c_ambient="0.1" c_diffuse="0.9" exp="10"><base_color r="1" g="0" b="1"/><specular_color r="0.5" g="0.5" b="0.5"/><reflective_color r="0.8" g="0" b="0.8"/></material></quad>
    <triangle_mesh src="scenes/meshes/torus-knot.obj" smooth="false">
      <material type="glass" ior="1.333"><refraction_color r="0" g="0.99" b="0"/></material>
      <transform><rotate x="0" y="1" z="0" angle="90"/></transform></triangle_mesh>
  </objects>
  <film width="800" height="600" size="0.008" gamma="1.0"/>
  <renderer type="raytracer" aa_samples="4" num_threads="2" sampler="hammersley" max_depth="5" min_contribution="0.01" seed="7"/>
  <camera type="orthographic" d="50.0" exposure="1.5"><eye x="-26" y="3.5" z="35"/><target x="0" y="0" z="0"/><up x="0" y="1" z="0"/></camera>
</scene>)",
                              test::source_path(""));
    CHECK(s.background == RGB(0.1f, 0.2f, 0.3f));
    CHECK(s.ambient.radiance().g == Approx(0.05f));
    REQUIRE(s.lights.points.size() == 1);
    CHECK(s.lights.points[0].attenuation == 0.5f);
    CHECK(s.lights.points[0].intensity == RGB(4.f));
    REQUIRE(s.lights.directionals.size() == 1);
    CHECK(s.lights.directionals[0].direction.y == Approx(-1.f));
    REQUIRE(s.lights.spots.size() == 1);
    CHECK(s.lights.spots[0].cos_outer == Approx(std::cos(30.f * kPi / 180.f)));
    CHECK(s.lights.spots[0].cos_inner == Approx(std::cos(15.f * kPi / 180.f)));
    REQUIRE(s.lights.areas.size() == 2);
    CHECK(s.lights.areas[0].samples == 9);
    CHECK(s.lights.areas[0].sampler == SamplerKind::Hammersley);
    CHECK(s.lights.areas[0].area == Approx(2.f));
    CHECK(s.lights.areas[0].normal.y == Approx(-1.f));  // edge1 x edge2 = (0, -2, 0)
    CHECK(s.lights.areas[1].area == Approx(2.f));
    CHECK(s.lights.areas[1].normal.y == Approx(-1.f));
    CHECK(s.lights.areas[1].radiance == RGB(2.f));
    CHECK(s.accel == AccelType::Embree);
    // 2 area-light emitters + sphere + quad + mesh.
    REQUIRE(s.objects.size() == 5);
    REQUIRE(s.spheres.size() == 1);
    CHECK(s.spheres[0].radius == Approx(4.f));
    CHECK(s.spheres[0].center.x == Approx(3.f));  // scaled then translated
    CHECK(s.materials[s.objects[2].material].type == MaterialType::Phong);
    CHECK(s.materials[s.objects[3].material].type == MaterialType::Reflective);
    CHECK(s.materials[s.objects[3].material].reflective_color == RGB(0.8f, 0.f, 0.8f));
    const Material& glass = s.materials[s.objects[4].material];
    CHECK(glass.type == MaterialType::Glass);
    CHECK(glass.ior == Approx(1.333f));
    CHECK_FALSE(s.objects[4].smooth);
    CHECK(s.meshes.back().num_triangles() == 4096);
    // Rotation by 90 degrees about y maps the knot's x extent onto z.
    CHECK(s.meshes.back().bounds().diagonal().z == Approx(2.88f).epsilon(0.02));
    CHECK(s.film.width == 800);
    CHECK(s.film.pixel_size == Approx(0.008f));
    CHECK(s.film.gamma == 1.f);
    CHECK(s.render.run.spp == 4);
    CHECK(s.render.run.threads == 2);
    CHECK(s.render.sampler == SamplerKind::Hammersley);
    CHECK(s.render.max_depth == 5);
    CHECK(s.render.run.seed == 7);
    CHECK(s.camera.type == CameraType::Orthographic);
    CHECK(s.camera.d == 50.f);
    CHECK(s.camera.exposure == 1.5f);
}

TEST_CASE("XML: fov sets the pixel size, and the shipped scenes load", "[xml][fast]") {
    const TestScene s = parse_scene(
        R"(<scene><film width="512" height="512"/><camera d="1" fov="39.3077"><eye x="278" y="277.5" z="-800"/><target x="278" y="277.5" z="0"/></camera>)" +
            std::string(kSphere) + "</scene>",
        "s.xml", ".");
    CHECK(s.camera.vertical_fov_degrees() == Approx(39.3077f));
    for (const char* f : {"cornell-box.xml", "cornell-mirror.xml", "bunny.xml", "torus-knot.xml"}) {
        const Scene sc = load_scene(test::source_path(std::string("scenes/") + f));
        CHECK_FALSE(sc.objects.empty());
    }
}

TEST_CASE("XML: every bad-input case names file and line", "[xml][bad-input][fast]") {
    SECTION("malformed XML") {
        expect_error("<scene>\n<film width=\"1\"\n</scene>", 3, "malformed XML");
    }
    SECTION("wrong root") {
        expect_error("<world/>", 1, "root element must be <scene>");
    }
    SECTION("unknown element") {
        expect_error(scene_xml("\n<teapot/>"), 5, "unknown element <teapot>");
    }
    SECTION("unknown attribute") {
        expect_error(scene_xml("\n<background r=\"0\" g=\"0\" b=\"0\" alpha=\"1\"/>"), 5,
                     "unknown attribute 'alpha'");
    }
    SECTION("unknown attribute values") {
        expect_error(scene_xml("\n<aggregate type=\"quadtree\"/>"), 5,
                     "unknown aggregate type 'quadtree'");
        expect_error(scene_xml("\n<renderer sampler=\"owen\"/>"), 5, "unknown sampler 'owen'");
        expect_error(scene_xml("\n<renderer type=\"magic\"/>"), 5, "unknown renderer type");
        expect_error(std::string("<scene>") + kFilmCamera +
                         "\n<objects><sphere radius=\"1\"><center x=\"0\" y=\"0\" z=\"0\"/>"
                         "<material type=\"velvet\"/></sphere></objects></scene>",
                     4, "unknown material type 'velvet'");
    }
    SECTION("missing mesh file") {
        expect_error(
            std::string("<scene>") + kFilmCamera +
                "\n<objects>\n<triangle_mesh src=\"nothere.obj\"><material type=\"matte\"/>"
                "</triangle_mesh></objects></scene>",
            5, "mesh file not found: 'nothere.obj'");
    }
    SECTION("face index out of range, reported in the OBJ file") {
        test::TempDir dir;
        std::ofstream(dir.file("bad.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n";
        try {
            parse(std::string("<scene>") + kFilmCamera +
                      "<objects><triangle_mesh src=\"bad.obj\"><material type=\"matte\"/>"
                      "</triangle_mesh></objects></scene>",
                  dir.path().string());
            FAIL("no error");
        } catch (const InputError& e) {
            CHECK_THAT(e.what(), Catch::Contains("bad.obj:4: vertex index 4 out of range"));
        }
    }
    SECTION("NaN and Inf numbers") {
        expect_error(scene_xml("\n<background r=\"nan\" g=\"0\" b=\"0\"/>"), 5, "NaN or infinite");
        expect_error(
            scene_xml("\n<lights><point><position x=\"inf\" y=\"0\" z=\"0\"/></point></lights>"), 5,
            "NaN or infinite");
        expect_error(scene_xml("\n<background r=\"zero\" g=\"0\" b=\"0\"/>"), 5, "not a number");
    }
    SECTION("negative or zero sizes") {
        expect_error(std::string("<scene>") + kFilmCamera +
                         "\n<objects><sphere radius=\"-1\"><center x=\"0\" y=\"0\" z=\"0\"/>"
                         "<material type=\"matte\"/></sphere></objects></scene>",
                     4, "radius must be positive");
        expect_error("<scene>\n<film width=\"-5\"/></scene>", 2, "positive integer");
        expect_error("<scene>\n<film size=\"0\"/></scene>", 2, "'size' must be positive");
        expect_error(
            scene_xml(
                "\n<lights><area><corner x=\"0\" y=\"0\" z=\"0\"/><edge1 x=\"1\" y=\"0\" z=\"0\"/>"
                "<edge2 x=\"2\" y=\"0\" z=\"0\"/></area></lights>"),
            5, "zero area");
        expect_error(scene_xml("\n<lights><point intensity=\"-1\"><position x=\"0\" y=\"0\" "
                               "z=\"0\"/></point></lights>"),
                     5, "must not be negative");
        expect_error(scene_xml("\n<renderer aa_samples=\"0\"/>"), 5, "positive integer");
        // Each attribute once, one root element (issue 34, defect 19): pugixml takes both.
        expect_error(scene_xml("\n<renderer spp=\"4\" spp=\"64\"/>"), 5, "'spp' given twice");
        expect_error(scene_xml("\n<lights><point intensity=\"1\" intensity=\"9\"><position "
                               "x=\"0\" y=\"0\" z=\"0\"/></point></lights>"),
                     5, "'intensity' given twice");
        expect_error(scene_xml("") + "\n" + scene_xml(""), 5, "second root element <scene>");
    }
    SECTION("empty scene") {
        expect_error(std::string("<scene>") + kFilmCamera + "\n<objects>\n</objects></scene>", 4,
                     "no objects");
        expect_error(std::string("<scene>") + kFilmCamera + "</scene>", 1, "needs a <objects>");
        expect_error(std::string("<scene>") + kSphere + "</scene>", 1, "needs a <film>");
    }
    SECTION("duplicated and inconsistent elements") {
        expect_error(scene_xml("\n<aggregate type=\"grid\"/>\n<aggregate type=\"grid\"/>"), 6,
                     "more than once");
        expect_error(
            "<scene><film/>\n<camera><eye x=\"0\" y=\"0\" z=\"0\"/><target x=\"0\" y=\"0\" "
            "z=\"0\"/></camera></scene>",
            2, "eye and target coincide");
    }
}

TEST_CASE("XML: physically based materials, emission, integrator settings", "[xml][fast]") {
    auto obj = [](const std::string& mat) {
        return "<sphere radius=\"1\"><center x=\"0\" y=\"0\" z=\"0\"/>" + mat + "</sphere>";
    };
    const TestScene s = parse(
        std::string("<scene>") + kFilmCamera + "<objects>" +
        obj(R"(<material type="lambert"><reflectance r="0.2" g="0.4" b="0.6"/></material>)") +
        obj(R"(<material type="oren_nayar" sigma="0.4"/>)") +
        obj(R"(<material type="conductor" preset="gold" roughness="0.1"/>)") +
        obj(R"(<material type="conductor"><eta r="0.2" g="0.9" b="1.1"/><k r="3.9" g="2.4" b="2.1"/></material>)") +
        obj(R"(<material type="dielectric" ior="1.33"/>)") +
        obj(R"(<material type="microfacet" distribution="ashikhmin_shirley" nu="10" nv="200" fresnel="conductor" preset="copper"/>)") +
        obj(R"(<material type="microfacet" model="cook_torrance" kd="0.7" ks="0.3"><diffuse r="0.5" g="0.5" b="0.5"/></material>)") +
        obj(R"(<material type="mix"><material type="lambert" weight="0.5"/><material type="conductor" weight="0.4"/>
                                 <emission r="1" g="2" b="3" two_sided="true"/></material>)") +
        obj(R"(<material type="microfacet" distribution="ggx" roughness="0.1" roughness_v="0.4" fresnel="conductor" preset="gold"/>)") +
        obj(R"(<material type="microfacet" distribution="ggx" roughness="0.2" fresnel="schlick" ior="1.5"/>)") +
        obj(R"(<material type="microfacet" distribution="ggx" roughness="0.2" fresnel="schlick" preset="gold"/>)") +
        R"(</objects><renderer type="path" spp="7" mis="max" nee="false" rr_depth="5" time="12">
                              <adaptive pilot="4" max_spp="64" threshold="0.05" unbiased="true"/></renderer></scene>)");
    REQUIRE(s.materials.size() == 11);
    CHECK(s.materials[0].bsdf.lobe(0).type == LobeType::Lambert);
    CHECK(s.materials[0].bsdf.lobe(0).color.b == 0.6f);
    CHECK(s.materials[1].bsdf.lobe(0).type == LobeType::OrenNayar);
    CHECK(s.materials[2].bsdf.lobe(0).type == LobeType::Microfacet);
    CHECK(s.materials[2].bsdf.lobe(0).fresnel.kind == FresnelKind::Conductor);
    CHECK(s.materials[3].bsdf.lobe(0).type == LobeType::Mirror);
    CHECK(s.materials[3].bsdf.lobe(0).fresnel.k.r == 3.9f);
    CHECK(s.materials[4].bsdf.lobe(0).type == LobeType::Dielectric);
    CHECK(s.materials[5].bsdf.lobe(0).dist.kind == MicrofacetKind::AshikhminShirley);
    CHECK(s.materials[5].bsdf.lobe(0).dist.nv == 200.f);
    REQUIRE(s.materials[6].bsdf.size() == 2);  // Cook-Torrance: diffuse + specular
    CHECK(s.materials[6].bsdf.lobe(0).color.r == Approx(0.35f));
    REQUIRE(s.materials[7].bsdf.size() == 2);
    CHECK(s.materials[7].bsdf.lobe(0).color.r == Approx(0.25f));  // 0.5 x the default 0.5
    CHECK(s.materials[7].emission.b == 3.f);
    const MicrofacetDistribution& ggx = s.materials[8].bsdf.lobe(0).dist;
    CHECK(ggx.kind == MicrofacetKind::TrowbridgeReitz);
    CHECK(ggx.alpha == 0.1f);
    CHECK(ggx.alpha_y == 0.4f);
    const Fresnel& glass = s.materials[9].bsdf.lobe(0).fresnel;
    CHECK(glass.kind == FresnelKind::Schlick);
    CHECK(glass.f0.g == Approx(0.04f));
    const Fresnel& metal = s.materials[10].bsdf.lobe(0).fresnel;
    CHECK(metal.kind == FresnelKind::Schlick);
    CHECK(metal.f0.r > metal.f0.b);  // gold: red reflects more than blue head-on
    CHECK(s.materials[7].emission_two_sided);
    CHECK(s.render.integrator == "path");
    CHECK(s.render.run.spp == 7);
    CHECK(s.render.mis == MisHeuristic::Maximum);
    CHECK_FALSE(s.render.nee);
    CHECK(s.render.rr_depth == 5);
    CHECK(s.render.run.time_limit == 12.f);
    CHECK(s.render.adaptive.enabled);
    CHECK(s.render.adaptive.unbiased);
    CHECK(s.render.adaptive.max_spp == 64);
    // The thesis' materials keep working and gain their physically based reading.
    const Scene t = parse(scene_xml(""));
    CHECK(t.materials[0].type == MaterialType::Matte);
    CHECK(t.materials[0].bsdf.lobe(0).type == LobeType::Lambert);
}

TEST_CASE("XML: bad physically based materials and renderer settings", "[xml][bad-input][fast]") {
    auto mat = [](const std::string& m) {
        return std::string("<scene>") + kFilmCamera +
               "<objects>\n<sphere radius=\"1\"><center x=\"0\" y=\"0\" z=\"0\"/>\n" + m +
               "</sphere></objects></scene>";
    };
    expect_error(mat(R"(<material type="velvet"/>)"), 5, "unknown material type 'velvet'");
    expect_error(mat(R"(<material type="microfacet" distribution="cauchy"/>)"), 5,
                 "unknown distribution 'cauchy'");
    expect_error(mat(R"(<material type="microfacet" distribution="ggx" roughness_v="3"/>)"), 5,
                 "roughness_v must be in [0.002, 2]");
    expect_error(mat(R"(<material type="microfacet" model="phong"/>)"), 5,
                 "unknown microfacet model");
    expect_error(mat(R"(<material type="microfacet" model="cook_torrance" kd="0.8" ks="0.5"/>)"), 5,
                 "kd + ks must be at most 1");
    expect_error(mat(R"(<material type="dielectric" roughness="0.2" distribution="blinn"/>)"), 5,
                 "a rough dielectric takes distribution=\"ggx\"");
    expect_error(mat(R"(<material type="dielectric" roughness="3"/>)"), 5,
                 "roughness must be in [0.002, 2]");
    expect_error(mat(R"(<material type="dielectric" distribution="ggx"/>)"), 5,
                 "a distribution needs a roughness above 0");
    expect_error(mat(R"(<material type="conductor" preset="unobtainium"/>)"), 5,
                 "unknown conductor preset");
    expect_error(mat(R"(<material type="mix"><material type="lambert" weight="0.7"/>
<material type="lambert" weight="0.6"/></material>)"),
                 5, "mix weights sum to more than 1");
    expect_error(mat(R"(<material type="oren_nayar" sigma="30"/>)"), 5, "radians");
    expect_error(
        mat(R"(<material type="lambert"><emission r="1" g="1" b="1" sampling="cone"/></material>)"),
        5, "unknown emitter sampling");
    expect_error(mat(R"(<material type="lambert" ior="1.5"/>)"), 5, "unknown attribute 'ior'");
    expect_error(scene_xml("\n<renderer type=\"bidirectional\"/>"), 5,
                 "unknown renderer type 'bidirectional'");
    expect_error(scene_xml("\n<renderer type=\"path\" mis=\"cubic\"/>"), 5,
                 "unknown mis heuristic 'cubic'");
    expect_error(scene_xml("\n<renderer><adaptive pilot=\"16\" max_spp=\"8\"/></renderer>"), 5,
                 "max_spp must be at least pilot");
}

TEST_CASE("XML: renderer settings are typed and checked by name, with their line",
          "[xml][bad-input][fast]") {
    expect_error(scene_xml("\n<renderer spp=\"4\" gather_ray=\"8\"/>"), 5,
                 "unknown setting 'gather_ray' (did you mean 'gather_rays'?)");
    expect_error(scene_xml("\n<renderer frobnicate=\"yes\"/>"), 5, "unknown setting 'frobnicate'");
    expect_error(scene_xml("\n<renderer cache_levels=\"9\"/>"), 5,
                 "setting 'cache_levels' must be an integer in [1, 8], not 9");
    expect_error(scene_xml("\n<renderer alpha=\"1.5\"/>"), 5, "alpha must be in (0, 1]");
    expect_error(scene_xml("\n<renderer filter=\"box\"/>"), 5,
                 "unknown filter 'box' (none, cone, gauss, simpson, gauss_thesis)");
    expect_error(scene_xml("\n<renderer nee=\"maybe\"/>"), 5, "must be true or false");
    expect_error(scene_xml("\n<renderer>\n<adaptive pilot=\"0\"/></renderer>"), 6,
                 "setting 'adaptive_pilot' must be a positive integer");
    // The same keys from the command line: later wins, errors name --set.
    const TestScene s = parse_scene(scene_xml("\n<renderer type=\"path\" spp=\"4\"/>"), "s.xml",
                                    ".", {{"spp", "9"}, {"mis", "balance"}, {"adaptive", "true"}});
    CHECK(s.render.run.spp == 9);
    CHECK(s.render.mis == MisHeuristic::Balance);
    CHECK(s.render.adaptive.enabled);
    try {
        const TestScene bad = parse_scene(scene_xml(""), "s.xml", ".", {{"mis", "cubic"}});
        FAIL("no error");
    } catch (const InputError& e) {
        CHECK_THAT(e.what(), Catch::Contains("--set: unknown mis heuristic 'cubic'"));
    }
    // One table of integrators: every name and alias is found, and an alias means its name.
    for (const IntegratorInfo& info : integrators()) {
        CHECK(find_integrator(info.name) == &info);
        for (const char* alias : info.aliases) CHECK(find_integrator(alias) == &info);
    }
    CHECK(TestScene(parse_scene(scene_xml("\n<renderer type=\"whitted\"/>"), "s.xml", "."))
              .render.integrator == "raytracer");
}

TEST_CASE("XML: panoramic cameras", "[xml][camera][fast]") {
    auto with_camera = [](const std::string& camera) {
        return std::string("<scene><film width=\"64\" height=\"32\"/>\n") + camera +
               "<eye x=\"0\" y=\"0\" z=\"5\"/><target x=\"0\" y=\"0\" z=\"0\"/></camera>" +
               kSphere + "</scene>";
    };
    const Scene e = parse(with_camera(R"(<camera type="equirectangular">)"));
    CHECK(e.camera.type == CameraType::Equirectangular);
    CHECK(parse(with_camera(R"(<camera type="panoramic">)")).camera.type ==
          CameraType::Equirectangular);
    const Scene f = parse(with_camera(R"(<camera type="fisheye" fov="200">)"));
    CHECK(f.camera.type == CameraType::Fisheye);
    CHECK(f.camera.fisheye_fov == Approx(200.f * kPi / 180.f));
    CHECK(parse(with_camera(R"(<camera type="fisheye">)")).camera.fisheye_fov == Approx(kPi));
    expect_error(with_camera(R"(<camera type="fisheye" fov="400">)"), 2,
                 "a fisheye's fov must be in (0, 360] degrees");
    expect_error(with_camera(R"(<camera type="equirectangular" fov="90">)"), 2,
                 "fov applies to perspective cameras only");
    expect_error(with_camera(R"(<camera type="spherical">)"), 2,
                 "unknown camera type 'spherical' (perspective, orthographic, equirectangular, "
                 "fisheye)");
}
