#include "tensor_file.h"

#include <cstring>

#include "error.h"
#include "input_file.h"

namespace foton {

namespace {

uint64_t type_size(TensorType t) {
    switch (t) {
        case TensorType::UInt8:
        case TensorType::Int8:
            return 1;
        case TensorType::UInt16:
        case TensorType::Int16:
        case TensorType::Float16:
            return 2;
        case TensorType::UInt32:
        case TensorType::Int32:
        case TensorType::Float32:
            return 4;
        case TensorType::UInt64:
        case TensorType::Int64:
        case TensorType::Float64:
            return 8;
        case TensorType::Invalid:
            break;
    }
    return 0;
}

// Little-endian reads from a byte string, every one checked against its end.
class Reader {
  public:
    Reader(const std::string& bytes, const std::string& path) : b_(bytes), path_(path) {}
    template <class T>
    T get() {
        T v;
        need(sizeof(T));
        std::memcpy(&v, b_.data() + at_, sizeof(T));
        at_ += sizeof(T);
        return v;
    }
    std::string text(std::size_t n) {
        need(n);
        std::string s = b_.substr(at_, n);
        at_ += n;
        return s;
    }
    [[noreturn]] void fail(const std::string& what) const {
        throw InputError(path_, 0, "not a valid tensor file (.bsdf): " + what);
    }

  private:
    void need(std::size_t n) const {
        if (n > b_.size() - at_) fail("it ends early (truncated?)");
    }
    const std::string& b_;
    const std::string& path_;
    std::size_t at_ = 0;
};

}  // namespace

uint64_t TensorField::count() const {
    uint64_t n = 1;
    for (uint64_t s : shape) n *= s;
    return n;
}

std::vector<float> TensorField::floats(const std::string& file, const std::string& name) const {
    std::vector<float> out(count());
    if (type == TensorType::Float32) {
        std::memcpy(out.data(), bytes.data(), out.size() * sizeof(float));
    } else if (type == TensorType::Float64) {
        for (std::size_t i = 0; i < out.size(); ++i) {
            double d;
            std::memcpy(&d, bytes.data() + i * sizeof(double), sizeof(double));
            out[i] = float(d);
        }
    } else {
        throw InputError(file, 0, "tensor field '" + name + "' holds no floating-point values");
    }
    return out;
}

const TensorField& TensorFile::field(const std::string& name, std::size_t rank) const {
    const auto it = fields.find(name);
    if (it == fields.end()) throw InputError(path, 0, "tensor file has no field '" + name + "'");
    if (it->second.shape.size() != rank)
        throw InputError(path, 0,
                         "tensor field '" + name + "' has " +
                             std::to_string(it->second.shape.size()) + " dimensions, not " +
                             std::to_string(rank));
    return it->second;
}

TensorFile parse_tensor_file(const std::string& bytes, const std::string& path) {
    Reader r(bytes, path);
    if (r.text(12) != std::string("tensor_file", 12)) r.fail("no 'tensor_file' header");
    const uint8_t major = r.get<uint8_t>(), minor = r.get<uint8_t>();
    if (major != 1 || minor != 0)
        r.fail("version " + std::to_string(major) + "." + std::to_string(minor) + " (1.0 is read)");
    const uint32_t n_fields = r.get<uint32_t>();
    if (n_fields > 1024) r.fail(std::to_string(n_fields) + " fields");
    TensorFile file;
    file.path = path;
    for (uint32_t i = 0; i < n_fields; ++i) {
        const uint16_t name_length = r.get<uint16_t>();
        const std::string name = r.text(name_length);
        const uint16_t rank = r.get<uint16_t>();
        const uint8_t type = r.get<uint8_t>();
        const uint64_t offset = r.get<uint64_t>();
        if (rank > 8) r.fail("field '" + name + "' of rank " + std::to_string(rank));
        if (type == 0 || type > uint8_t(TensorType::Float64))
            r.fail("field '" + name + "' of unknown type " + std::to_string(type));
        TensorField f;
        f.type = TensorType(type);
        uint64_t size = type_size(f.type);
        for (uint16_t d = 0; d < rank; ++d) {
            const uint64_t extent = r.get<uint64_t>();
            if (extent != 0 && size > (uint64_t(1) << 40) / extent)
                r.fail("field '" + name + "' is too large");
            size *= extent;
            f.shape.push_back(extent);
        }
        if (offset > bytes.size() || size > bytes.size() - offset)
            r.fail("field '" + name + "' lies beyond the file's end");
        f.bytes.assign(bytes.begin() + std::ptrdiff_t(offset),
                       bytes.begin() + std::ptrdiff_t(offset + size));
        file.fields[name] = std::move(f);
    }
    return file;
}

TensorFile read_tensor_file(const std::string& path, uint64_t max_bytes) {
    return parse_tensor_file(read_input_file(path, max_bytes, "tensor file"), path);
}

}  // namespace foton
