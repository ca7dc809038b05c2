// Golden image hashes: every shipped scene rendered at 32x24 with every integrator (and the
// irradiance cache under path and photon) must give the very same pixels as when the table in
// tests/data/image_hashes/ was made. It guards restructurings of the transport code, which
// must not change a single bit. A change that is meant to alter images regenerates the table
// with scripts/regenerate_image_hashes, whose reason is logged beside the hashes.
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include "engine/accel/intersector.h"
#include "engine/core/error.h"
#include "engine/core/hash.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/integrators.h"
#include "engine/transport/registry/render.h"
#include "test_util.h"

using namespace foton;

namespace {

struct Config {
    const char* name;
    RendererOverrides settings;
    uint32_t passes = 1;    // progressive passes (RenderOptions::max_passes)
    bool adaptive = false;  // adaptive sampling: pilot 2, at most 8 per pixel
};

// Small enough that all scenes x configurations take well under a minute on two cores, large
// enough that every stage (photon maps, gathers, cache records, adaptive rounds) runs.
const std::vector<Config>& configs() {
    static const RendererOverrides small_photons = {
        {"global_photons", "4000"}, {"caustic_photons", "4000"}, {"gather_rays", "8"}, {"k", "20"},
        {"caustic_k", "10"},        {"guide_photons", "50"}};
    static const RendererOverrides small_cache = {{"indirect", "irradiance_cache"},
                                                  {"cache_samples", "32"}};
    auto with = [](RendererOverrides a, const RendererOverrides& b) {
        a.insert(a.end(), b.begin(), b.end());
        return a;
    };
    // Scenes that ask for the irradiance cache get it only in the -cache configurations.
    const RendererOverrides no_cache = {{"indirect", "final_gather"}};
    // Every row of the integrator table gets a configuration of its name (a new integrator's
    // hashes are recorded by FOTON_REGENERATE_IMAGE_HASHES); those that need small settings
    // to run fast at this size name them here.
    const std::map<std::string, RendererOverrides> small = {{"photon", small_photons}};
    static const std::vector<Config> all = [&] {
        std::vector<Config> list;
        for (const IntegratorInfo& i : integrators()) {
            auto it = small.find(i.name);
            list.push_back({i.name, with(with({{"type", i.name}},
                                              it == small.end() ? RendererOverrides{} : it->second),
                                         no_cache)});
        }
        // Variations that pin a feature's own code path.
        const std::vector<Config> variations = {
            {"path-bsdf", with({{"type", "path"}, {"nee", "false"}}, no_cache)},
            {"path-cache", with({{"type", "path"}}, small_cache)},
            {"path-passes", with({{"type", "path"}}, no_cache), 3},
            {"path-adaptive", with({{"type", "path"}}, no_cache), 1, true},
            {"light-passes", with({{"type", "light"}}, no_cache), 2},
            {"photon-direct", with(with({{"type", "photon"},
                                         {"mode", "direct_visualisation"},
                                         {"split_direct", "true"}},
                                        small_photons),
                                   no_cache)},
            {"photon-cache", with(with({{"type", "photon"}}, small_photons), small_cache)},
            // A cache per bounce, three deep: the next level's lookups and their visibility rays.
            {"photon-cache-levels",
             with(with({{"type", "photon"}, {"cache_secondary", "cache"}, {"cache_levels", "3"}},
                       small_photons),
                  {{"indirect", "irradiance_cache"}, {"cache_samples", "16"}})},
            // Shadow photons deciding the shadow rays they can (Jensen 1995).
            {"photon-shadow", with(with({{"type", "photon"},
                                         {"shadow_photons", "true"},
                                         {"shadow_visibility", "estimate"}},
                                        small_photons),
                                   no_cache)},
            {"sppm-passes", with({{"type", "sppm"}}, no_cache), 3},
            {"ppm-passes", with({{"type", "ppm"}}, no_cache), 3},
            {"vcm-passes", with({{"type", "vcm"}}, no_cache), 3},
        };
        list.insert(list.end(), variations.begin(), variations.end());
        return list;
    }();
    return all;
}

// The hash of the image, or "error" when the configuration does not apply to the scene
// (the light tracer behind a thin lens, photon mapping without a light).
std::string image_hash(const std::string& path, const Config& c) {
    Scene scene;
    RenderSettings settings;
    try {
        scene = load_scene(path, c.settings);
        settings = render_settings(scene);
    } catch (const InputError&) {
        return "error";
    }
    scene.set_resolution(32, 24);
    if (c.adaptive) {
        settings.adaptive.enabled = true;
        settings.adaptive.pilot = 2;
        settings.adaptive.max_spp = 8;
        settings.adaptive.threshold = 0.05f;
    }
    const auto accel = make_intersector(scene, AccelType::Bvh, 2);
    RenderOptions opt;
    opt.threads = 2;
    opt.spp = 2;
    opt.seed = 7;
    opt.max_passes = c.passes;
    opt.time_limit = c.passes > 1 ? 1e6f : 0.f;
    RenderResult r;
    try {
        r = render(scene, settings, *accel, opt);
    } catch (const InputError&) {
        return "error";
    }
    uint64_t h = fnv1a(&r.film.width, sizeof r.film.width);
    h = fnv1a(&r.film.height, sizeof r.film.height, h);
    h = fnv1a(r.film.pixels.data(), r.film.pixels.size() * sizeof(RGB), h);
    char buf[24];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
    return buf;
}

std::string table_path(const std::string& scene) {
    return test::source_path("tests/data/image_hashes/" + scene + ".txt");
}

void check_scene(const std::string& name) {
    const std::string path = test::source_path("scenes/" + name + ".xml");
    std::map<std::string, std::string> now;
    for (const Config& c : configs()) now[c.name] = image_hash(path, c);

    if (const char* regen = std::getenv("FOTON_REGENERATE_IMAGE_HASHES"); regen && *regen) {
        std::ofstream out(table_path(name));
        out << "# configuration  image hash (tests/test_golden_images.cpp)\n";
        for (const auto& [config, hash] : now) out << config << ' ' << hash << '\n';
        WARN("regenerated " << table_path(name));
        return;
    }
    std::ifstream in(table_path(name));
    REQUIRE(in);
    std::map<std::string, std::string> expected;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream ls(line);
        std::string config, hash;
        ls >> config >> hash;
        expected[config] = hash;
    }
    for (const auto& [config, hash] : now) {
        INFO(name << " / " << config);
        CHECK(expected.count(config) == 1);
        CHECK(expected[config] == hash);
    }
}

}  // namespace

TEST_CASE("golden image hashes: bunny", "[golden]") {
    check_scene("bunny");
}
TEST_CASE("golden image hashes: cache-leak", "[golden]") {
    check_scene("cache-leak");
}
TEST_CASE("golden image hashes: cornell-box", "[golden]") {
    check_scene("cornell-box");
}
TEST_CASE("golden image hashes: cornell-caustics", "[golden]") {
    check_scene("cornell-caustics");
}
TEST_CASE("golden image hashes: cornell-empty", "[golden]") {
    check_scene("cornell-empty");
}
// Participating media: volpath's configuration renders it, the others refuse it ("error").
TEST_CASE("golden image hashes: cornell-fog", "[golden]") {
    check_scene("cornell-fog");
}
TEST_CASE("golden image hashes: smoke", "[golden]") {
    check_scene("smoke");
}
TEST_CASE("golden image hashes: cornell-glass-caustic", "[golden]") {
    check_scene("cornell-glass-caustic");
}

TEST_CASE("golden image hashes: cornell-diffuse", "[golden]") {
    check_scene("cornell-diffuse");
}
TEST_CASE("golden image hashes: cornell-mirror", "[golden]") {
    check_scene("cornell-mirror");
}
TEST_CASE("golden image hashes: cornell-spot-ceiling", "[golden]") {
    check_scene("cornell-spot-ceiling");
}
TEST_CASE("golden image hashes: cornell-table", "[golden]") {
    check_scene("cornell-table");
}
TEST_CASE("golden image hashes: dragon", "[golden]") {
    check_scene("dragon");
}
TEST_CASE("golden image hashes: materials", "[golden]") {
    check_scene("materials");
}
TEST_CASE("golden image hashes: mis-plates", "[golden]") {
    check_scene("mis-plates");
}
TEST_CASE("golden image hashes: torus-knot", "[golden]") {
    check_scene("torus-knot");
}
TEST_CASE("golden image hashes: smallvcm-box", "[golden]") {
    check_scene("smallvcm-box");
}
