// foton: the command line. Subcommands render, info and compare.
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "engine/core/error.h"

int main(int argc, char** argv) {
    using namespace foton;
    CLI::App app{"foton: a research renderer for global illumination"};
    app.set_version_flag("--version", std::string("foton ") + FOTON_VERSION);
    app.require_subcommand(1);

    app::RenderArgs ra;
    CLI::App* render = app.add_subcommand("render", "render a scene to OpenEXR (+ PNG preview)");
    render->add_option("scene", ra.scene, "scene XML file")->required();
    render->add_option("-o,--output", ra.output, "output .exr (default out/<scene>.exr)");
    render->add_option("--spp", ra.spp, "samples per pixel (overrides aa_samples)");
    render->add_option("--threads", ra.threads, "worker threads (0 = all)");
    render->add_option("--seed", ra.seed, "random seed");
    render->add_option("--accel", ra.accel, "brute | brute-simd | grid | embree");
    render->add_option("--width", ra.width, "image width in pixels (keeps the field of view)");
    render->add_option("--height", ra.height, "image height in pixels");
    render->add_flag("--stats", ra.stats, "print ray counts and the stage table");
    render->add_option("--stats-json", ra.stats_json, "write statistics as JSON");
    render->add_flag("-q,--quiet", ra.quiet, "no progress bar or summary");

    std::string info_scene;
    CLI::App* info = app.add_subcommand("info", "print a scene summary");
    info->add_option("scene", info_scene, "scene XML file")->required();

    app::CompareArgs ca;
    CLI::App* compare = app.add_subcommand("compare", "error metrics between two EXR images");
    compare->add_option("a", ca.a, "image")->required();
    compare->add_option("b", ca.b, "reference image")->required();
    compare->add_option("--diff", ca.diff_png, "write a false-colour difference PNG");
    compare->add_option("--diff-scale", ca.diff_scale, "error that maps to white (default 0.1)");

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        app.exit(e);
        return kExitBadInput;
    }
    try {
        if (*render) return app::run_render(ra);
        if (*info) return app::run_info(info_scene);
        if (*compare) return app::run_compare(ca);
    } catch (const InputError& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return kExitBadInput;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "foton: internal error: %s\n", e.what());
        return kExitInternal;
    }
    return kExitInternal;
}
