// Projection maps for directional and environment lights (engine/scene/projection_map.h,
// environment_projection.h; the photon-mapping thesis, 5.3.2): the photons of a distant light
// at a small scene start over its geometry (>= 90 % of them hit it, against the whole bounding
// disc's fraction without the map), every ray from the sky through geometry starts in a kept
// cell, every kept point's density is the one pdf_le reports, and the images keep their mean.
#include <catch2/catch.hpp>

#include "engine/accel/intersector.h"
#include "engine/core/rng.h"
#include "engine/film/metrics.h"
#include "engine/scene/light_set.h"
#include "engine/scene/xml_loader.h"
#include "test_util.h"

using namespace foton;

namespace {

// A small scene under a distant light at 40 degrees: a 4 x 4 floor and two spheres.
const char* kScene = R"(<scene><lights>
    <directional intensity="2"><color r="1" g="0.95" b="0.9"/><direction x="0.5" y="-1" z="0.3"/></directional>
  </lights><objects>
    <quad><corner x="-2" y="0" z="-2"/><edge1 x="0" y="0" z="4"/><edge2 x="4" y="0" z="0"/>
      <material type="lambert"><reflectance r="0.8" g="0.8" b="0.8"/></material></quad>
    <sphere radius="0.6"><center x="-0.6" y="0.6" z="0"/>
      <material type="lambert"><reflectance r="0.7" g="0.3" b="0.2"/></material></sphere>
    <sphere radius="0.4"><center x="0.9" y="1.5" z="0.5"/>
      <material type="lambert"><reflectance r="0.2" g="0.4" b="0.7"/></material></sphere>
  </objects><film width="32" height="24"/><renderer type="photon" global_photons="50000"/>
  <camera fov="45"><eye x="0" y="3" z="-6"/><target x="0" y="0.5" z="0"/></camera></scene>)";

// The same scene under a sky (an image with a bright sun, importance-sampled) instead.
std::string sky_scene() {
    std::string s = kScene;
    const std::size_t a = s.find("<directional"), b = s.find("</lights>");
    return s.replace(a, b - a,
                     "<environment src=\"" + test::source_path("scenes/meshes/sky.hdr") +
                         "\" intensity=\"1\"><up x=\"0\" y=\"1\" z=\"0\"/></environment>");
}

// n rays emitted by `lights` (numbers of stream `stream`) and where they hit the scene; a
// sample that carries no light (a spot's direction past its cone) is left out.
struct Emitted {
    RayBatch rays;
    HitBatch hits;
    // The number of rays that hit and, of those, how many `kept(dir, hit point)` accepts.
    template <class Kept>
    std::pair<uint32_t, uint32_t> hits_kept(Kept&& kept) const {
        uint32_t hit = 0, covered = 0;
        for (uint32_t i = 0; i < rays.size(); ++i) {
            if (hits.geom[i] == kNoHit) continue;
            ++hit;
            covered += kept(rays.direction(i), rays.origin(i) + rays.direction(i) * hits.t[i]);
        }
        return {hit, covered};
    }
};
Emitted emit(const Scene& scene, const LightSet& lights, uint32_t n, uint64_t stream) {
    Emitted e;
    for (uint32_t i = 0; i < n; ++i) {
        EmittedRay er;
        auto u = [&](uint32_t dim) { return rng::uniform(stream, 0, i, dim); };
        if (lights.sample_ray(u(0), {u(1), u(2)}, {u(3), u(4)}, u(5), er))
            e.rays.push(er.origin, er.emission.dir, 0.f, kInfinity, i);
    }
    TraceCounters ts;
    make_intersector(scene, scene.accel)->intersect(e.rays, e.hits, ts);
    return e;
}

// The fraction of n emitted rays that hit the scene.
double hit_fraction(const Scene& scene, const LightSet& lights, uint32_t n) {
    return double(emit(scene, lights, n, 3)
                      .hits_kept([](const Vec3&, const Vec3&) { return true; })
                      .first) /
           n;
}

// The means of photon mapping's and the light tracer's images of `s` with and without
// projection maps agree within 2 % (the light tracer's paths are per pixel: more of them).
void check_means_kept(TestScene s) {
    for (const char* type : {"photon", "light"}) {
        INFO(type);
        s.render.integrator = type;
        const uint32_t spp = std::string(type) == "light" ? 128 : 16;
        s.render.projection_maps = true;
        const Film a = render_test(s, spp, 0, 5).film;
        s.render.projection_maps = false;
        const Film b = render_test(s, spp, 0, 5).film;
        const ImageError e = compare_images(a, b);
        INFO("means " << e.mean_a.g << " with the maps, " << e.mean_b.g << " without");
        CHECK(e.mean_a.r == Approx(e.mean_b.r).epsilon(0.02));
        CHECK(e.mean_a.g == Approx(e.mean_b.g).epsilon(0.02));
        CHECK(e.mean_a.b == Approx(e.mean_b.b).epsilon(0.02));
    }
}

}  // namespace

TEST_CASE("projection maps: a distant light's photons start over the geometry",
          "[photon][projection][fast]") {
    const TestScene scene = parse_scene(kScene, "p.xml", ".");
    const LightSet with(scene, LightSelection::Power, true),
        without(scene, LightSelection::Power, false);
    REQUIRE(with.size() == 1);
    const ProjectionMap& map = with.projection_map(0);
    REQUIRE(!map.empty());
    REQUIRE(without.projection_map(0).empty());
    const double f_with = hit_fraction(scene, with, 20000);
    const double f_without = hit_fraction(scene, without, 20000);
    INFO("hit fraction with the map " << f_with << ", without " << f_without << ", kept cells "
                                      << map.coverage());
    CHECK(f_with >= 0.9);
    CHECK(f_without < 0.8 * f_with);
    // The density the emission reports is pdf_le's, and the power it carries is the light's
    // radiance over the kept area: beta = Le / (pmf pdf_pos).
    const float r = with.scene_radius();
    float pdf_pos, pdf_dir;
    with.pdf_le(0, {}, with.emitter(0).n, pdf_pos, pdf_dir);
    CHECK(pdf_pos == Approx(1.f / map.area()));
    CHECK(map.area() < kPi * r * r);
    EmittedRay er;
    REQUIRE(with.sample_ray(0.5f, {0.3f, 0.7f}, {0.1f, 0.2f}, 0.f, er));
    CHECK(er.emission.pdf_pos == Approx(pdf_pos));
    CHECK(er.beta.g == Approx(with.emitter(0).value.g * map.area()));
}

TEST_CASE("projection maps: photon mapping's image keeps its mean", "[photon][projection]") {
    TestScene scene = parse_scene(kScene, "p.xml", ".");
    const Film a = render_test(scene, 16, 0, 5).film;
    scene.render.projection_maps = false;
    const Film b = render_test(scene, 16, 0, 5).film;
    const ImageError e = compare_images(a, b);
    INFO("means " << e.mean_a.g << " with the map, " << e.mean_b.g << " without");
    CHECK(e.mean_a.r == Approx(e.mean_b.r).epsilon(0.02));
    CHECK(e.mean_a.g == Approx(e.mean_b.g).epsilon(0.02));
    CHECK(e.mean_a.b == Approx(e.mean_b.b).epsilon(0.02));
}

TEST_CASE(
    "environment projection maps: sky photons start over the geometry, and every ray "
    "through it is kept",
    "[photon][projection][environment]") {
    const TestScene scene = parse_scene(sky_scene(), "p.xml", ".");
    const LightSet with(scene, LightSelection::Power, true),
        without(scene, LightSelection::Power, false);
    REQUIRE(with.size() == 1);
    REQUIRE(without.environment_projection() == nullptr);
    const EnvironmentProjection* maps = with.environment_projection();
    REQUIRE(maps != nullptr);
    const double f_with = hit_fraction(scene, with, 40000);
    const double f_without = hit_fraction(scene, without, 40000);
    INFO("hit fraction with the maps " << f_with << ", without " << f_without
                                       << ", kept area / disc " << maps->kept_fraction());
    // Not the directional map's 90 %: a bin's map serves a cone of directions, so it keeps
    // the voxels' outline grown by how far the cone shifts it (docs/results.md).
    CHECK(f_with >= 0.6);
    CHECK(f_with > 1.8 * f_without);
    // Conservative: the rays of the whole disc that hit something all start in a kept cell of
    // their direction's map (were one not, the maps would lose its light).
    const auto [hit, covered] =
        emit(scene, without, 40000, 5).hits_kept([&](const Vec3& d, const Vec3& p) {
            return maps->covers(-d, p);
        });
    REQUIRE(hit > 1000);
    CHECK(covered == hit);
    // The density of each emitted ray is pdf_le's for its direction, and the ray starts
    // outside the bounding sphere.
    for (uint32_t i = 0; i < 200; ++i) {
        EmittedRay er;
        REQUIRE(with.sample_ray(rng::uniform(6, 0, i, 0),
                                {rng::uniform(6, 0, i, 1), rng::uniform(6, 0, i, 2)},
                                {rng::uniform(6, 0, i, 3), rng::uniform(6, 0, i, 4)}, 0.f, er));
        float pdf_pos, pdf_dir;
        with.pdf_le(0, er.emission.n, er.emission.dir, pdf_pos, pdf_dir);
        CHECK(pdf_pos == Approx(er.emission.pdf_pos).epsilon(1e-5));
        CHECK(maps->covers(-er.emission.dir, er.origin));
        CHECK(length(er.origin - scene.bounds().center()) > with.scene_radius());
    }
}

TEST_CASE("environment projection maps: photon mapping and light tracing keep their means",
          "[photon][projection][environment]") {
    check_means_kept(parse_scene(sky_scene(), "p.xml", "."));
}

namespace {

// The floor and spheres lit by a point light, or by a wide spot, above them.
std::string point_scene(bool spot) {
    std::string s = kScene;
    const std::size_t a = s.find("<directional"), b = s.find("</lights>");
    const std::string light =
        spot ? R"(<spot intensity="6" angle="70"><color r="1" g="0.9" b="0.8"/>)"
               R"(<position x="0.3" y="3" z="-0.5"/><target x="0" y="0" z="0"/></spot>)"
             : R"(<point intensity="6"><color r="1" g="0.9" b="0.8"/>)"
               R"(<position x="0.3" y="3" z="-0.5"/></point>)";
    return s.replace(a, b - a, light);
}

}  // namespace

TEST_CASE(
    "point and spot projection maps: photons leave only towards the geometry, and every "
    "direction that reaches it is kept",
    "[photon][projection][point]") {
    for (const bool spot : {false, true}) {
        INFO((spot ? "spot" : "point"));
        const TestScene scene = parse_scene(point_scene(spot), "p.xml", ".");
        const LightSet with(scene, LightSelection::Power, true),
            without(scene, LightSelection::Power, false);
        REQUIRE(with.size() == 1);
        REQUIRE(without.direction_projection(0) == nullptr);
        const DirectionProjection* maps = with.direction_projection(0);
        REQUIRE(maps != nullptr);
        const double f_with = hit_fraction(scene, with, 40000);
        const double f_without = hit_fraction(scene, without, 40000);
        INFO("hit fraction with the map " << f_with << ", without " << f_without
                                          << ", kept solid angle " << maps->kept_fraction());
        CHECK(f_with >= 0.75);
        CHECK(f_with > 1.3 * f_without);
        // Conservative: every direction of the light's own sampling that hits geometry has a
        // density under the map; and a drawn direction's density is pdf_le's.
        const auto [hit, covered] =
            emit(scene, without, 40000, 8).hits_kept([&](const Vec3& d, const Vec3&) {
                return maps->pdf(d) > 0.f;
            });
        REQUIRE(hit > 1000);
        CHECK(covered == hit);
        for (uint32_t i = 0; i < 200; ++i) {
            EmittedRay er;
            if (!with.sample_ray(0.5f, {0.5f, 0.5f},
                                 {rng::uniform(9, 0, i, 0), rng::uniform(9, 0, i, 1)}, 0.f, er))
                continue;
            float pdf_pos, pdf_dir;
            with.pdf_le(0, {}, er.emission.dir, pdf_pos, pdf_dir);
            CHECK(pdf_dir == Approx(er.emission.pdf_dir).epsilon(1e-3));
        }
        // Photon mapping's and the light tracer's images keep their means.
        check_means_kept(parse_scene(point_scene(spot), "p.xml", "."));
    }
}
