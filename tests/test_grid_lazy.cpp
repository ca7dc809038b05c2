// The lazy nested grid (the ray-tracing thesis' 8.1.1): mesh grids built when a ray first
// reaches them give the eager grids' hits exactly, and meshes no ray reaches are never built.
#include <catch2/catch.hpp>
#include <string>

#include "engine/accel/grid_accel.h"
#include "engine/core/rng.h"
#include "engine/scene/xml_loader.h"
#include "test_util.h"

using namespace foton;

namespace {

// Eight quads (each a mesh with its own grid): four in front of the origin (+z), four behind.
Scene quads(bool lazy) {
    std::string objects;
    for (int i = 0; i < 8; ++i) {
        const float z = i < 4 ? 5.f + float(i) : -5.f - float(i);
        const float x = float(i % 4) * 0.5f - 1.f;
        objects += "<quad><corner x=\"" + std::to_string(x) + "\" y=\"-1\" z=\"" +
                   std::to_string(z) +
                   "\"/><edge1 x=\"0.4\" y=\"0\" z=\"0.1\"/><edge2 x=\"0\" y=\"2\" z=\"0\"/>"
                   "<material type=\"lambert\"/></quad>";
    }
    return parse_scene(
        std::string("<scene><film width=\"8\" height=\"8\"/><aggregate type=\"grid\"") +
            (lazy ? " lazy=\"true\"" : "") + "/><objects>" + objects +
            "</objects><camera><eye x=\"0\" y=\"0\" z=\"0\"/><target x=\"0\" "
            "y=\"0\" z=\"1\"/></camera></scene>",
        "lazy.xml", ".");
}

}  // namespace

TEST_CASE("lazy nested grid: the eager grid's hits, and unreached meshes never built",
          "[accel][fast]") {
    const Scene eager_scene = quads(false), lazy_scene = quads(true);
    CHECK(lazy_scene.grid_lazy);
    const GridAccel eager(eager_scene), lazy(lazy_scene);
    CHECK(eager.built_grids() == 8);
    CHECK(lazy.built_grids() == 0);
    RayBatch rays;
    for (int i = 0; i < 20000; ++i) {
        // Rays from the origin into the +z half-space only.
        const Vec3 d = normalize(Vec3{rng::uniform(8, 1, uint64_t(i), 0) * 0.8f - 0.4f,
                                      rng::uniform(8, 1, uint64_t(i), 1) * 0.8f - 0.4f, 1.f});
        rays.push({0, 0, 0}, d, 0.f, kInfinity, uint32_t(i));
    }
    HitBatch he, hl;
    TraceCounters c;
    eager.intersect(rays, he, c);
    lazy.intersect(rays, hl, c);
    std::size_t same = 0, hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        same +=
            (he.geom[i] == hl.geom[i] && he.t[i] == hl.t[i] && he.prim[i] == hl.prim[i]) ? 1 : 0;
        hits += he.geom[i] != kNoHit ? 1 : 0;
    }
    CHECK(same == rays.size());
    CHECK(hits > 1000);
    // Only the quads in front were reached; the four behind stay unbuilt.
    CHECK(lazy.built_grids() == 4);
    std::vector<uint8_t> oe, ol;
    eager.occluded(rays, oe, c);
    lazy.occluded(rays, ol, c);
    CHECK(oe == ol);
    CHECK(lazy.memory_bytes() < eager.memory_bytes());
    // A render with the lazy grid (threads racing to build) is the eager render.
    TestScene te(eager_scene), tl(lazy_scene);
    te.render.integrator = tl.render.integrator = "ao";
    const auto ae = make_intersector(te, AccelType::Grid),
               al = make_intersector(tl, AccelType::Grid);
    RenderOptions opt;
    opt.spp = 4;
    opt.threads = 3;
    CHECK(render(te, te.render, *ae, opt).film.pixels ==
          render(tl, tl.render, *al, opt).film.pixels);
}
