// Shadow photons' lines (Jensen 1995) are traced as batches after a chunk's first hits; the
// map they make must be the one a photon-by-photon walk makes, photon for photon and in the
// same order, on every backend (the kd-tree, and so the image, depends on the order).
#include <catch2/catch.hpp>

#include <cstring>

#include "engine/accel/intersector.h"
#include "engine/scene/light_set.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/photon/photon_tracer.h"
#include "test_util.h"

using namespace foton;

namespace {

// FNV-1a over every field of every photon, in map order.
uint64_t map_hash(const PhotonMap& m) {
    uint64_t h = 1469598103934665603ull;
    auto mix = [&](const void* p, std::size_t n) {
        const unsigned char* b = static_cast<const unsigned char*>(p);
        for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
    };
    for (std::size_t i = 0; i < m.size(); ++i) {
        const Vec3 p = m.position(i), w = m.incident(i), n = m.normal(i);
        const RGB& c = m.power(i);
        const float f[12] = {p.x, p.y, p.z, w.x, w.y, w.z, n.x, n.y, n.z, c.r, c.g, c.b};
        mix(f, sizeof f);
        const uint8_t flags = m.flags(i);
        const uint16_t light = m.light(i);
        mix(&flags, 1);
        mix(&light, 2);
    }
    return h;
}

}  // namespace

TEST_CASE("shadow photon lines: the photon-by-photon walk's map on every backend", "[photon]") {
    // Light from the ceiling: lines through the spheres and onto the floor behind them.
    const TestScene s = load_scene(test::source_path("scenes/cornell-diffuse.xml"));
    const LightSet lights(s);
    PhotonPassSettings ps;
    ps.emitted = 6000;  // two chunks, the second partial
    ps.max_depth = 4;
    ps.shadow_photons = true;
    for (AccelType a : {AccelType::Brute, AccelType::Grid, AccelType::Bvh, AccelType::Embree}) {
        INFO(accel_name(a));
        const auto acc = make_intersector(s, a);
        const PhotonTracer tracer(s, *acc, lights, 7);
        RenderStats st;
        PhotonMap shadow;
        const PhotonMap global = tracer.run(ps, st, &shadow);
        CHECK(global.size() > 0);
        CHECK(shadow.size() > 500);
        // Recorded from the photon-by-photon walk (intersect1 per crossing) at commit c5f0baa.
        CHECK(map_hash(shadow) == 0xc8270f6e119ab100ull);
    }
}
