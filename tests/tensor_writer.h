#pragma once
// Writes Mitsuba tensor files (engine/core/tensor_file.h) for the tests: the measured
// materials' .bsdf files are tensors of float and byte fields.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/core/tensor_file.h"

namespace foton::test {

struct TensorOut {
    std::string name;
    TensorType type = TensorType::Float32;
    std::vector<uint64_t> shape;
    std::string bytes;  // the elements as stored
};

inline TensorOut float_tensor(const std::string& name, std::vector<uint64_t> shape,
                              const std::vector<float>& v) {
    return {name, TensorType::Float32, std::move(shape),
            std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(float))};
}

inline std::string tensor_bytes(const std::vector<TensorOut>& fields) {
    std::string header("tensor_file", 12);
    header += char(1);
    header += char(0);
    auto put = [](std::string& s, const auto& v) {
        s.append(reinterpret_cast<const char*>(&v), sizeof(v));
    };
    put(header, uint32_t(fields.size()));
    std::size_t header_size = header.size();
    for (const TensorOut& f : fields)
        header_size += 2 + f.name.size() + 2 + 1 + 8 + 8 * f.shape.size();
    std::string data;
    for (const TensorOut& f : fields) {
        put(header, uint16_t(f.name.size()));
        header += f.name;
        put(header, uint16_t(f.shape.size()));
        header += char(f.type);
        put(header, uint64_t(header_size + data.size()));
        for (uint64_t s : f.shape) put(header, s);
        data += f.bytes;
    }
    return header + data;
}

}  // namespace foton::test
