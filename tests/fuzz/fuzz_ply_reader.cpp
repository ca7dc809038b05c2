// libFuzzer harness: the PLY reader (ASCII and binary). Bad input must end as InputError.
#include <cstddef>
#include <cstdint>
#include <string>

#include "engine/core/error.h"
#include "engine/scene/ply_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    try {
        (void)foton::parse_ply(std::string(reinterpret_cast<const char*>(data), size), "fuzz.ply");
    } catch (const foton::InputError&) {
    }
    return 0;
}
