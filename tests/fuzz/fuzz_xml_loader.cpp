// libFuzzer harness: the XML scene loader and the renderer's typed settings. The input is a
// scene file, optionally followed by a line "--set" and key=value lines (the command line's
// overrides). Bad input must end as InputError; anything else (a crash, a sanitizer report,
// another exception) is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "engine/core/error.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/integrators.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const std::string input(reinterpret_cast<const char*>(data), size);
    std::string xml = input;
    foton::RendererOverrides overrides;
    const std::size_t marker = input.find("\n--set\n");
    if (marker != std::string::npos) {
        xml = input.substr(0, marker);
        std::size_t at = marker + 7;
        while (at < input.size()) {
            std::size_t end = input.find('\n', at);
            if (end == std::string::npos) end = input.size();
            const std::string line = input.substr(at, end - at);
            const std::size_t eq = line.find('=');
            if (eq != std::string::npos)
                overrides.emplace_back(line.substr(0, eq), line.substr(eq + 1));
            at = end + 1;
        }
    }
    try {
        // Meshes resolve against a directory that does not exist: the fuzzer reads no files.
        const foton::Scene scene =
            foton::parse_scene(xml, "fuzz.xml", "/nonexistent-foton-fuzz", overrides);
        (void)foton::render_settings(scene);
        (void)scene.summary();
    } catch (const foton::InputError&) {
    }
    return 0;
}
