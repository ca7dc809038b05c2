// Cancellation inside passes (issue 34, defect 11 and the server's stop): a render whose
// cancel flag is set traces no further chunk of whatever it is in, pre-passes included (photon
// tracing, the irradiance cache's fill, the guide's photons), instead of finishing a pass of
// millions of photons first. Checked by what was traced, not by time: with the flag set from
// the start, nothing is.
#include <atomic>
#include <catch2/catch.hpp>
#include <cmath>

#include "engine/accel/intersector.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/render.h"
#include "test_util.h"

using namespace foton;

namespace {

struct Cancelled {
    RenderResult result;
    bool finite = true;
};

// The caustics box at 32 x 32 under `type` with `settings` (--set style), cancelled before
// it starts.
Cancelled render_cancelled(const std::string& type,
                           const std::vector<std::pair<std::string, std::string>>& settings) {
    RendererOverrides over{{"type", type}};
    for (const auto& kv : settings) over.push_back(kv);
    Scene scene = load_scene(test::source_path("scenes/cornell-caustics.xml"), over);
    scene.set_resolution(32, 32);
    const std::unique_ptr<Intersector> accel = make_intersector(scene, AccelType::Bvh, 2);
    static const std::atomic<bool> stop{true};
    RenderOptions opt;
    opt.threads = 2;
    opt.spp = 4;
    opt.cancel = &stop;
    Cancelled c;
    c.result = render(scene, *accel, opt);
    for (const RGB& p : c.result.film.pixels)
        if (!std::isfinite(p.r) || !std::isfinite(p.g) || !std::isfinite(p.b)) c.finite = false;
    return c;
}

}  // namespace

TEST_CASE("Cancelled photon mapping traces no photon of its 10 M and no camera sample",
          "[cancel][fast]") {
    const Cancelled c = render_cancelled(
        "photon", {{"global_photons", "10000000"}, {"caustic_photons", "10000000"}});
    CHECK(c.result.stats.photons_global == 0);
    CHECK(c.result.stats.photons_caustic == 0);
    CHECK(c.result.stats.samples == 0);
    CHECK(c.finite);
}

TEST_CASE("A cancelled irradiance cache fill computes no record", "[cancel][fast]") {
    const Cancelled c =
        render_cancelled("path", {{"indirect", "irradiance_cache"}, {"cache_samples", "4096"}});
    CHECK(c.result.stats.cache_stored == 0);
    CHECK(c.result.stats.samples == 0);
    CHECK(c.finite);
}

TEST_CASE("A cancelled guided path tracer traces no guide photon", "[cancel][fast]") {
    const Cancelled c =
        render_cancelled("path", {{"guided", "true"}, {"guide_emitted", "20000000"}});
    CHECK(c.result.stats.photons_global == 0);
    CHECK(c.result.stats.samples == 0);
}

TEST_CASE("Cancelled light tracing, SPPM and VCM trace no path", "[cancel][fast]") {
    for (const char* type : {"light", "sppm", "vcm", "bdpt"}) {
        INFO(type);
        const Cancelled c = render_cancelled(type, {});
        CHECK(c.result.stats.total_rays() == 0);
        CHECK(c.finite);
    }
}
