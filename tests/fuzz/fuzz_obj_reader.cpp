// libFuzzer harness: the OBJ reader. Bad input must end as InputError with its line.
#include <cstddef>
#include <cstdint>
#include <string>

#include "engine/core/error.h"
#include "engine/scene/obj_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    try {
        (void)foton::parse_obj(std::string(reinterpret_cast<const char*>(data), size), "fuzz.obj");
    } catch (const foton::InputError&) {
    }
    return 0;
}
