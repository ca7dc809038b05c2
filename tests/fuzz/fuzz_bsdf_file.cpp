// libFuzzer harness: the tensor-file reader and the measured BRDF built from it (pbrt-v4's
// "measured" material's .bsdf files). Bad input must end as InputError.
#include <cstddef>
#include <cstdint>
#include <string>

#include "engine/core/error.h"
#include "engine/core/tensor_file.h"
#include "engine/scene/measured_brdf.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    try {
        const foton::TensorFile t = foton::parse_tensor_file(
            std::string(reinterpret_cast<const char*>(data), size), "fuzz.bsdf");
        (void)foton::measured_brdf_from(t);
    } catch (const foton::InputError&) {
    }
    return 0;
}
