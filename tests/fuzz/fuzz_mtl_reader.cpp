// libFuzzer harness: the MTL reader. Bad input must end as InputError.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/core/error.h"
#include "engine/scene/mesh_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    std::vector<std::string> notes;
    try {
        (void)foton::parse_mtl(std::string(reinterpret_cast<const char*>(data), size), "fuzz.mtl",
                               ".", notes);
    } catch (const foton::InputError&) {
    }
    return 0;
}
