// libFuzzer harness: the glTF loader (tinygltf's parser, then our checks of every index,
// accessor, buffer view and image), as JSON or, when the input starts with "glTF", as .glb.
// External files resolve against a directory that does not exist; data URIs still decode.
// Bad input must end as InputError.
#include <cstddef>
#include <cstdint>
#include <string>

#include "engine/core/error.h"
#include "engine/scene/mesh_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    try {
        (void)foton::parse_gltf(bytes, "fuzz.gltf", "/nonexistent-fuzz-dir",
                                bytes.rfind("glTF", 0) == 0);
    } catch (const foton::InputError&) {
    }
    return 0;
}
