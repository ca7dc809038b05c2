// libFuzzer harness: the PFM reader (colour and grey, both byte orders). Bad input must end
// as InputError.
#include <cstddef>
#include <cstdint>
#include <string>

#include "engine/core/error.h"
#include "engine/film/pfm_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    try {
        (void)foton::parse_pfm(std::string(reinterpret_cast<const char*>(data), size), "fuzz.pfm");
    } catch (const foton::InputError&) {
    }
    return 0;
}
