// libFuzzer harness: the pbrt-v4 importer on a scene in memory (Include and plymesh paths
// resolve against a directory with no such files). Bad input must end as InputError.
#include <cstddef>
#include <cstdint>
#include <string>

#include "engine/core/error.h"
#include "engine/scene/pbrt_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    try {
        (void)foton::parse_pbrt_scene(std::string(reinterpret_cast<const char*>(data), size),
                                      "fuzz.pbrt", "/nonexistent-fuzz-dir");
    } catch (const foton::InputError&) {
    }
    return 0;
}
