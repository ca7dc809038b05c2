#include "ply_reader.h"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <sstream>
#include <vector>

#include "engine/core/decompress.h"
#include "engine/core/error.h"
#include "engine/core/input_file.h"

namespace foton {

namespace {

enum class Scalar { I8, U8, I16, U16, I32, U32, F32, F64 };

bool scalar_of(const std::string& s, Scalar& out) {
    static const std::pair<const char*, Scalar> names[] = {
        {"char", Scalar::I8},    {"int8", Scalar::I8},     {"uchar", Scalar::U8},
        {"uint8", Scalar::U8},   {"short", Scalar::I16},   {"int16", Scalar::I16},
        {"ushort", Scalar::U16}, {"uint16", Scalar::U16},  {"int", Scalar::I32},
        {"int32", Scalar::I32},  {"uint", Scalar::U32},    {"uint32", Scalar::U32},
        {"float", Scalar::F32},  {"float32", Scalar::F32}, {"double", Scalar::F64},
        {"float64", Scalar::F64}};
    for (const auto& [n, t] : names)
        if (s == n) {
            out = t;
            return true;
        }
    return false;
}

std::size_t size_of(Scalar t) {
    switch (t) {
        case Scalar::I8:
        case Scalar::U8:
            return 1;
        case Scalar::I16:
        case Scalar::U16:
            return 2;
        case Scalar::I32:
        case Scalar::U32:
        case Scalar::F32:
            return 4;
        case Scalar::F64:
            return 8;
    }
    return 1;
}

struct Property {
    std::string name;
    Scalar type = Scalar::F32;
    bool list = false;
    Scalar count_type = Scalar::U8;
};

struct Element {
    std::string name;
    uint64_t count = 0;
    std::vector<Property> props;
    int line = 0;
};

enum class Format { Ascii, Little, Big };

// A scalar of type T from its bytes in native order.
template <class T>
double as(const unsigned char* raw) {
    T v;
    std::memcpy(&v, raw, sizeof v);
    return double(v);
}

class Reader {
  public:
    Reader(const std::string& bytes, const std::string& name) : b_(bytes), name_(name) {}
    TriangleMesh run();

  private:
    [[noreturn]] void fail(int line, const std::string& what) const {
        throw InputError(name_, line, what);
    }
    [[noreturn]] void fail_at(const std::string& what) const {
        if (format_ == Format::Ascii) fail(line_, what);
        fail(0, "byte " + std::to_string(pos_) + ": " + what);
    }
    void header();
    double value(Scalar t);
    // A list property's length, read and checked.
    uint32_t list_length(const Property& p) {
        const double n = value(p.count_type);
        if (!(n >= 0.0 && n <= 1e6)) fail_at("bad list length");
        return uint32_t(n);
    }
    std::string_view ascii_token();

    const std::string& b_;
    const std::string& name_;
    std::size_t pos_ = 0;
    int line_ = 1;
    Format format_ = Format::Ascii;
    std::vector<Element> elements_;
};

void Reader::header() {
    auto next_line = [&]() {
        const std::size_t end = b_.find('\n', pos_);
        if (end == std::string::npos) fail(line_, "the header has no end_header");
        std::string l = b_.substr(pos_, end - pos_);
        if (!l.empty() && l.back() == '\r') l.pop_back();
        pos_ = end + 1;
        ++line_;
        return l;
    };
    if (next_line() != "ply") fail(1, "not a PLY file (the first line must be 'ply')");
    bool have_format = false;
    for (;;) {
        const int at = line_;
        std::istringstream in(next_line());
        std::string key;
        in >> key;
        if (key == "end_header") break;
        if (key == "comment" || key == "obj_info" || key.empty()) continue;
        if (key == "format") {
            std::string f, version;
            in >> f >> version;
            if (f == "ascii")
                format_ = Format::Ascii;
            else if (f == "binary_little_endian")
                format_ = Format::Little;
            else if (f == "binary_big_endian")
                format_ = Format::Big;
            else
                fail(at, "unknown PLY format '" + f + "'");
            if (version != "1.0") fail(at, "unsupported PLY version '" + version + "'");
            have_format = true;
        } else if (key == "element") {
            Element e;
            std::string count;
            in >> e.name >> count;
            uint64_t n = 0;
            auto [ptr, ec] = std::from_chars(count.data(), count.data() + count.size(), n);
            if (e.name.empty() || ec != std::errc() || ptr != count.data() + count.size())
                fail(at, "malformed element line (expected: element NAME COUNT)");
            // Every entry takes at least one byte: a count beyond the file is a lie.
            if (n > b_.size()) fail(at, "element '" + e.name + "' count exceeds the file size");
            e.count = n;
            e.line = at;
            elements_.push_back(e);
        } else if (key == "property") {
            if (elements_.empty()) fail(at, "property before any element");
            Property p;
            std::string t;
            in >> t;
            if (t == "list") {
                std::string ct, it;
                in >> ct >> it >> p.name;
                if (!scalar_of(ct, p.count_type) || !scalar_of(it, p.type))
                    fail(at, "unknown list property types '" + ct + " " + it + "'");
                if (p.count_type == Scalar::F32 || p.count_type == Scalar::F64)
                    fail(at, "a list count must be an integer type");
                p.list = true;
            } else {
                in >> p.name;
                if (!scalar_of(t, p.type)) fail(at, "unknown property type '" + t + "'");
            }
            if (p.name.empty()) fail(at, "property without a name");
            elements_.back().props.push_back(p);
        } else {
            fail(at, "unknown header keyword '" + key + "'");
        }
    }
    if (!have_format) fail(line_, "the header has no format line");
}

std::string_view Reader::ascii_token() {
    for (;;) {
        while (pos_ < b_.size() && (b_[pos_] == ' ' || b_[pos_] == '\t' || b_[pos_] == '\r'))
            ++pos_;
        if (pos_ < b_.size() && b_[pos_] == '\n') {
            ++pos_;
            ++line_;
            continue;
        }
        break;
    }
    const std::size_t s = pos_;
    while (pos_ < b_.size() && !std::isspace((unsigned char)b_[pos_])) ++pos_;
    if (s == pos_) fail_at("unexpected end of file");
    return {b_.data() + s, pos_ - s};
}

double Reader::value(Scalar t) {
    if (format_ == Format::Ascii) {
        const std::string_view tok = ascii_token();
        double v = 0.0;
        auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
        if (ec != std::errc() || ptr != tok.data() + tok.size() || !std::isfinite(v))
            fail_at("'" + std::string(tok) + "' is not a finite number");
        return v;
    }
    const std::size_t n = size_of(t);
    if (pos_ + n > b_.size()) fail_at("unexpected end of file");
    unsigned char raw[8];
    std::memcpy(raw, b_.data() + pos_, n);
    const bool swap = (format_ == Format::Big) == (std::endian::native == std::endian::little);
    if (swap)
        for (std::size_t i = 0; i < n / 2; ++i) std::swap(raw[i], raw[n - 1 - i]);
    pos_ += n;
    switch (t) {
        case Scalar::I8:
            return as<int8_t>(raw);
        case Scalar::U8:
            return as<uint8_t>(raw);
        case Scalar::I16:
            return as<int16_t>(raw);
        case Scalar::U16:
            return as<uint16_t>(raw);
        case Scalar::I32:
            return as<int32_t>(raw);
        case Scalar::U32:
            return as<uint32_t>(raw);
        case Scalar::F32:
            return as<float>(raw);
        case Scalar::F64:
            return as<double>(raw);
    }
    return 0.0;
}

TriangleMesh Reader::run() {
    header();
    TriangleMesh m;
    bool have_vertices = false;
    for (const Element& e : elements_) {
        if (e.name == "vertex") {
            if (have_vertices) fail(e.line, "a second vertex element");
            have_vertices = true;
            int slot[8];  // x y z nx ny nz u v -> property index
            const char* names[8][3] = {{"x"},
                                       {"y"},
                                       {"z"},
                                       {"nx"},
                                       {"ny"},
                                       {"nz"},
                                       {"u", "s", "texture_u"},
                                       {"v", "t", "texture_v"}};
            for (int k = 0; k < 8; ++k) {
                slot[k] = -1;
                for (std::size_t i = 0; i < e.props.size(); ++i)
                    for (const char* n : names[k])
                        if (n && e.props[i].name == n && !e.props[i].list) slot[k] = int(i);
            }
            if (slot[0] < 0 || slot[1] < 0 || slot[2] < 0)
                fail(e.line, "the vertex element needs x, y and z properties");
            const bool normals = slot[3] >= 0 && slot[4] >= 0 && slot[5] >= 0;
            const bool uvs = slot[6] >= 0 && slot[7] >= 0;
            std::vector<double> row(e.props.size());
            for (uint64_t v = 0; v < e.count; ++v) {
                for (std::size_t i = 0; i < e.props.size(); ++i) {
                    if (e.props[i].list) fail_at("list properties on vertices are not supported");
                    row[i] = value(e.props[i].type);
                }
                for (int k = 0; k < 3; ++k) {
                    const float x = float(row[std::size_t(slot[k])]);
                    if (!std::isfinite(x))
                        fail_at("vertex " + std::to_string(v) + " is not finite");
                    m.positions.push_back(x);
                }
                if (normals)
                    for (int k = 3; k < 6; ++k)
                        m.normals.push_back(float(row[std::size_t(slot[k])]));
                if (uvs)
                    for (int k = 6; k < 8; ++k) m.uvs.push_back(float(row[std::size_t(slot[k])]));
            }
        } else if (e.name == "face") {
            int slot = -1;
            for (std::size_t i = 0; i < e.props.size(); ++i)
                if (e.props[i].list &&
                    (e.props[i].name == "vertex_indices" || e.props[i].name == "vertex_index"))
                    slot = int(i);
            if (slot < 0) fail(e.line, "the face element needs a vertex_indices list");
            std::vector<uint32_t> poly;
            for (uint64_t f = 0; f < e.count; ++f) {
                for (std::size_t i = 0; i < e.props.size(); ++i) {
                    const Property& p = e.props[i];
                    if (!p.list) {
                        value(p.type);
                        continue;
                    }
                    const uint32_t n = list_length(p);
                    poly.clear();
                    for (uint32_t k = 0; k < n; ++k) {
                        const double idx = value(p.type);
                        if (int(i) != slot) continue;
                        if (!(idx >= 0.0 && idx < 4294967295.0) || idx != std::floor(idx))
                            fail_at("face " + std::to_string(f) + ": bad vertex index");
                        poly.push_back(uint32_t(idx));
                    }
                    if (int(i) != slot) continue;
                    if (poly.size() < 3)
                        fail_at("face " + std::to_string(f) + " has fewer than 3 vertices");
                    for (std::size_t k = 1; k + 1 < poly.size(); ++k)
                        m.indices.insert(m.indices.end(), {poly[0], poly[k], poly[k + 1]});
                }
            }
        } else {
            // Other elements (edges, materials...) are read past.
            for (uint64_t r = 0; r < e.count; ++r)
                for (const Property& p : e.props) {
                    const uint32_t n = p.list ? list_length(p) : 1;
                    for (uint32_t k = 0; k < n; ++k) value(p.type);
                }
        }
    }
    if (!have_vertices) fail(0, "no vertex element");
    if (m.indices.empty()) fail(0, "no faces");
    const std::size_t nv = m.num_vertices();
    for (uint32_t i : m.indices)
        if (i >= nv)
            fail(0, "a face refers to vertex " + std::to_string(i) + " of " + std::to_string(nv));
    return m;
}

}  // namespace

TriangleMesh parse_ply(const std::string& bytes, const std::string& name) {
    return Reader(bytes, name).run();
}

TriangleMesh load_ply(const std::string& path) {
    // .ply.gz and .ply.xz as public scene collections ship them.
    return parse_ply(read_input_file_decompressed(path, kMaxMeshFileBytes, "mesh file"), path);
}

}  // namespace foton
