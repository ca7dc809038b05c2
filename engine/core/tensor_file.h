#pragma once
// Mitsuba's tensor file format, in which the RGL material database ships its measured
// materials (`.bsdf`, read by pbrt-v4's "measured" material): a 12-byte "tensor_file" magic,
// version 1.0, a field count, then per field its name, rank, element type, data offset and
// shape (little-endian), the data elsewhere in the file. Every offset and size is checked
// against the file, so a truncated or hostile file is bad input naming the file, never a read
// past its end.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace foton {

enum class TensorType : uint8_t {
    Invalid = 0,
    UInt8,
    Int8,
    UInt16,
    Int16,
    UInt32,
    Int32,
    UInt64,
    Int64,
    Float16,
    Float32,
    Float64,
};

struct TensorField {
    TensorType type = TensorType::Invalid;
    std::vector<uint64_t> shape;
    std::vector<uint8_t> bytes;  // the elements as stored
    uint64_t count() const;
    // The elements as floats (Float32 or Float64 fields; InputError at `file` otherwise).
    std::vector<float> floats(const std::string& file, const std::string& name) const;
};

struct TensorFile {
    std::string path;
    std::map<std::string, TensorField> fields;
    // The field `name` with `rank` dimensions; InputError naming the file when it is missing or
    // of another rank.
    const TensorField& field(const std::string& name, std::size_t rank) const;
};

// Reads `path` (at most max_bytes); InputError(path, 0, ...) on any malformed content.
TensorFile read_tensor_file(const std::string& path, uint64_t max_bytes);
// The same from bytes already read (`path` names them in messages).
TensorFile parse_tensor_file(const std::string& bytes, const std::string& path);

}  // namespace foton
