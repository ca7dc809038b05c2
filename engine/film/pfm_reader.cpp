#include "pfm_reader.h"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>

#include "engine/core/error.h"
#include "engine/core/input_file.h"
#include "image_io.h"

namespace foton {

namespace {

// The header's tokens: each ends at whitespace; `line` counts the newlines passed.
struct Header {
    const std::string& bytes;
    const std::string& name;
    std::size_t at = 0;
    int line = 1;
    std::string token() {
        while (at < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[at]))) {
            if (bytes[at] == '\n') ++line;
            ++at;
        }
        const std::size_t begin = at;
        while (at < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[at])) &&
               at - begin < 64)
            ++at;
        return bytes.substr(begin, at - begin);
    }
    [[noreturn]] void fail(const std::string& what) const { throw InputError(name, line, what); }
};

}  // namespace

Film parse_pfm(const std::string& bytes, const std::string& name) {
    Header h{bytes, name};
    const std::string magic = h.token();
    if (magic != "PF" && magic != "Pf")
        h.fail("not a PFM image (it starts with '" + magic.substr(0, 8) + "', not PF or Pf)");
    const int channels = magic == "PF" ? 3 : 1;
    auto integer = [&](const char* what) {
        const std::string t = h.token();
        int v = 0;
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
        if (ec != std::errc() || end != t.data() + t.size() || v <= 0)
            h.fail(std::string("PFM ") + what + " '" + t + "' is not a positive integer");
        return v;
    };
    const int width = integer("width"), height = integer("height");
    const std::string st = h.token();
    char* end = nullptr;
    const float scale = std::strtof(st.c_str(), &end);
    if (st.empty() || end != st.c_str() + st.size() || !std::isfinite(scale) || scale == 0.f)
        h.fail("PFM scale '" + st + "' is not a finite non-zero number");
    const uint64_t pixels = uint64_t(width) * uint64_t(height);
    if (pixels > kMaxInputPixels)
        h.fail("image size " + std::to_string(width) + "x" + std::to_string(height) +
               " is out of range (at most " + std::to_string(kMaxInputPixels) + " pixels)");
    // One whitespace character ends the header; the floats follow.
    const std::size_t data = h.at + 1;
    const uint64_t need = pixels * uint64_t(channels) * 4;
    if (data > bytes.size() || bytes.size() - data < need)
        throw InputError(name, 0,
                         "PFM data is short: " + std::to_string(width) + "x" +
                             std::to_string(height) + (channels == 3 ? " RGB" : " grey") +
                             " needs " + std::to_string(need) +
                             " bytes after the header, the file has " +
                             std::to_string(data > bytes.size() ? 0 : bytes.size() - data));
    const bool little = scale < 0.f;
    const float k = std::fabs(scale);
    Film film(width, height);
    for (int y = 0; y < height; ++y) {
        // Rows are stored from the bottom up.
        const std::size_t row =
            data + std::size_t(height - 1 - y) * std::size_t(width) * std::size_t(channels) * 4;
        for (int x = 0; x < width; ++x) {
            float v[3];
            for (int c = 0; c < channels; ++c) {
                uint32_t u;
                std::memcpy(&u,
                            bytes.data() + row +
                                (std::size_t(x) * std::size_t(channels) + std::size_t(c)) * 4,
                            4);
                if (little != (std::endian::native == std::endian::little))
                    u = __builtin_bswap32(u);
                v[c] = std::bit_cast<float>(u) * k;
            }
            film.pixels[std::size_t(y) * std::size_t(width) + std::size_t(x)] =
                channels == 3 ? RGB{v[0], v[1], v[2]} : RGB{v[0]};
        }
    }
    return film;
}

Film read_pfm(const std::string& path) {
    return parse_pfm(read_input_file(path, kMaxMeshFileBytes, "image"), path);
}

}  // namespace foton
