#include "image_io.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfMatrixAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>
#include <unistd.h>

#include "engine/core/error.h"
#include "file_write.h"

namespace foton {

namespace {
// An OpenEXR output stream into memory (it seeks back to fill in the line offsets).
class MemoryStream : public Imf::OStream {
  public:
    explicit MemoryStream(const std::string& name) : Imf::OStream(name.c_str()) {}
    void write(const char c[], int n) override {
        if (pos_ + std::size_t(n) > data_.size()) data_.resize(pos_ + std::size_t(n));
        std::memcpy(data_.data() + pos_, c, std::size_t(n));
        pos_ += std::size_t(n);
    }
    uint64_t tellp() override { return pos_; }
    void seekp(uint64_t pos) override { pos_ = std::size_t(pos); }
    const std::string& bytes() const { return data_; }

  private:
    std::string data_;
    std::size_t pos_ = 0;
};
}  // namespace

std::string encode_exr(const std::string& path, const Film& film, const ImageAttributes& attrs,
                       const ExrRenderInfo& info) {
    {
        const int dw = info.display_width > 0 ? info.display_width : film.width;
        const int dh = info.display_height > 0 ? info.display_height : film.height;
        const Imath::Box2i display(Imath::V2i(0, 0), Imath::V2i(dw - 1, dh - 1));
        const Imath::Box2i data(Imath::V2i(info.x0, info.y0),
                                Imath::V2i(info.x0 + film.width - 1, info.y0 + film.height - 1));
        Imf::Header header(display, data);
        for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
        const bool samples = info.samples && info.samples->size() == film.pixels.size();
        if (info.samples && !samples)
            throw std::logic_error("encode_exr: the samples do not match the film's pixels");
        if (samples) header.channels().insert("samples", Imf::Channel(Imf::UINT));
        if (info.layers)
            for (const AovLayer& l : *info.layers) {
                if (l.values.size() != l.stride() * film.pixels.size())
                    throw std::logic_error("encode_exr: layer " + l.name +
                                           " does not match the film's pixels");
                for (const std::string& c : l.channels)
                    header.channels().insert(c, Imf::Channel(Imf::FLOAT));
            }
        for (const auto& [k, v] : attrs) header.insert(k, Imf::StringAttribute(v));
        // foton's RGB is linear with the sRGB / Rec. 709 primaries and D65 white: OpenEXR's
        // default chromaticities, written out so that readers need not assume them.
        Imf::addChromaticities(header, Imf::Chromaticities());
        auto m44 = [](const std::array<float, 16>& m) {
            return Imath::M44f(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], m[9], m[10],
                               m[11], m[12], m[13], m[14], m[15]);
        };
        if (info.world_to_camera) Imf::addWorldToCamera(header, m44(*info.world_to_camera));
        if (info.world_to_ndc) Imf::addWorldToNDC(header, m44(*info.world_to_ndc));
        if (info.render_seconds >= 0.f)
            header.insert("renderTimeSeconds", Imf::FloatAttribute(info.render_seconds));
        if (info.samples_per_pixel >= 0)
            header.insert("samplesPerPixel", Imf::IntAttribute(info.samples_per_pixel));
        if (info.mse) header.insert("MSE", Imf::FloatAttribute(*info.mse));
        // Encoded in memory (the offset table OpenEXR writes on closing included): written
        // whole by write_file_bytes, which checks every write, or served as it is.
        MemoryStream stream(path);
        std::optional<Imf::OutputFile> file;
        file.emplace(stream, header);
        Imf::FrameBuffer fb;
        // Slices address pixels by data-window coordinates.
        char* base = reinterpret_cast<char*>(const_cast<RGB*>(film.pixels.data())) -
                     (std::ptrdiff_t(info.x0) + std::ptrdiff_t(info.y0) * film.width) *
                         std::ptrdiff_t(sizeof(RGB));
        const std::size_t xs = sizeof(RGB), ys = sizeof(RGB) * std::size_t(film.width);
        fb.insert("R", Imf::Slice(Imf::FLOAT, base + offsetof(RGB, r), xs, ys));
        fb.insert("G", Imf::Slice(Imf::FLOAT, base + offsetof(RGB, g), xs, ys));
        fb.insert("B", Imf::Slice(Imf::FLOAT, base + offsetof(RGB, b), xs, ys));
        if (samples) {
            char* counts = reinterpret_cast<char*>(const_cast<uint32_t*>(info.samples->data())) -
                           (std::ptrdiff_t(info.x0) + std::ptrdiff_t(info.y0) * film.width) *
                               std::ptrdiff_t(sizeof(uint32_t));
            fb.insert("samples", Imf::Slice(Imf::UINT, counts, sizeof(uint32_t),
                                            sizeof(uint32_t) * std::size_t(film.width)));
        }
        if (info.layers)
            for (const AovLayer& l : *info.layers) {
                const std::size_t px = sizeof(float) * l.stride();
                char* first = reinterpret_cast<char*>(const_cast<float*>(l.values.data())) -
                              (std::ptrdiff_t(info.x0) + std::ptrdiff_t(info.y0) * film.width) *
                                  std::ptrdiff_t(px);
                for (std::size_t c = 0; c < l.stride(); ++c)
                    fb.insert(l.channels[c], Imf::Slice(Imf::FLOAT, first + c * sizeof(float), px,
                                                        px * std::size_t(film.width)));
            }
        file->setFrameBuffer(fb);
        file->writePixels(film.height);
        file.reset();
        return stream.bytes();
    }
}

void write_exr(const std::string& path, const Film& film, const ImageAttributes& attrs,
               const ExrRenderInfo& info) {
    write_file_bytes(path, encode_exr(path, film, attrs, info));
}

void check_claimed_size(const std::string& path, int width, int height, uint64_t pixels_per_byte) {
    std::error_code ec;
    const uint64_t bytes = std::filesystem::file_size(path, ec);
    const uint64_t pixels = uint64_t(std::max(width, 0)) * uint64_t(std::max(height, 0));
    if (width <= 0 || height <= 0 || pixels > kMaxInputPixels)
        throw InputError(path, 0,
                         "image size " + std::to_string(width) + "x" + std::to_string(height) +
                             " is out of range (at most " + std::to_string(kMaxInputPixels) +
                             " pixels)");
    if (!ec && pixels > bytes * pixels_per_byte)
        throw InputError(path, 0,
                         "the header claims " + std::to_string(width) + "x" +
                             std::to_string(height) + " pixels in a file of " +
                             std::to_string(bytes) + " bytes: a corrupt header");
}

namespace {
// The named channels of an OpenEXR file as float, interleaved per pixel over the data window.
// A channel the file lacks is an error when `required`, else 0 (OpenEXR's fill).
std::vector<float> read_float_channels(const std::string& path,
                                       const std::vector<std::string>& names, bool required,
                                       int& width, int& height) {
    if (!std::filesystem::is_regular_file(path)) throw InputError(path, 0, "no such image file");
    try {
        Imf::InputFile file(path.c_str());
        const Imath::Box2i dw = file.header().dataWindow();
        width = dw.max.x - dw.min.x + 1;
        height = dw.max.y - dw.min.y + 1;
        // Half-float RGB is 6 bytes a pixel before compression; no OpenEXR codec packs a
        // pixel into less than 1/256 of a byte.
        check_claimed_size(path, width, height, 256);
        if (required)
            for (const std::string& n : names)
                if (!file.header().channels().findChannel(n))
                    throw InputError(path, 0, "the image has no channel '" + n + "'");
        const std::size_t stride = names.size() * sizeof(float);
        std::vector<float> values(std::size_t(width) * std::size_t(height) * names.size());
        // Slices address pixels by data-window coordinates.
        char* base =
            reinterpret_cast<char*>(values.data()) -
            (std::ptrdiff_t(dw.min.x) + std::ptrdiff_t(dw.min.y) * width) * std::ptrdiff_t(stride);
        Imf::FrameBuffer fb;
        for (std::size_t c = 0; c < names.size(); ++c)
            fb.insert(names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), stride,
                                           stride * std::size_t(width)));
        file.setFrameBuffer(fb);
        file.readPixels(dw.min.y, dw.max.y);
        return values;
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError(path, 0, std::string("cannot read OpenEXR image: ") + e.what());
    }
}
}  // namespace

Film read_exr(const std::string& path) {
    static_assert(sizeof(RGB) == 3 * sizeof(float), "a film pixel is three floats");
    int w = 0, h = 0;
    const std::vector<float> v = read_float_channels(path, {"R", "G", "B"}, false, w, h);
    Film film(w, h);
    std::memcpy(static_cast<void*>(film.pixels.data()), v.data(), v.size() * sizeof(float));
    return film;
}

std::vector<float> read_exr_channels(const std::string& path, const std::vector<std::string>& names,
                                     int& width, int& height) {
    return read_float_channels(path, names, true, width, height);
}

ImageAttributes read_exr_attributes(const std::string& path) {
    if (!std::filesystem::is_regular_file(path)) throw InputError(path, 0, "no such image file");
    try {
        Imf::InputFile file(path.c_str());
        ImageAttributes out;
        for (auto it = file.header().begin(); it != file.header().end(); ++it)
            if (const auto* a = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
                out.emplace_back(it.name(), a->value());
            else if (const auto* f = dynamic_cast<const Imf::FloatAttribute*>(&it.attribute()))
                out.emplace_back(it.name(), std::to_string(f->value()));
            else if (const auto* i = dynamic_cast<const Imf::IntAttribute*>(&it.attribute()))
                out.emplace_back(it.name(), std::to_string(i->value()));
            else if (const auto* m = dynamic_cast<const Imf::M44fAttribute*>(&it.attribute())) {
                // The 16 entries row by row, each exactly.
                std::string text;
                for (int r = 0; r < 4; ++r)
                    for (int c = 0; c < 4; ++c) {
                        char buf[32];
                        std::snprintf(buf, sizeof buf, "%.9g", double(m->value()[r][c]));
                        if (!text.empty()) text += ' ';
                        text += buf;
                    }
                out.emplace_back(it.name(), text);
            }
        return out;
    } catch (const std::exception& e) {
        throw InputError(path, 0, std::string("cannot read OpenEXR image: ") + e.what());
    }
}

namespace {
// 8-bit sRGB-ish bytes of the preview: clamp(exposure * L, 0, 1)^(1 / gamma).
std::vector<unsigned char> tone_map(const Film& film, float exposure, float gamma) {
    std::vector<unsigned char> px(std::size_t(film.width) * std::size_t(film.height) * 3);
    const float inv_gamma = 1.f / gamma;
    auto encode = [&](float v) {
        v = std::clamp(v * exposure, 0.f, 1.f);
        return static_cast<unsigned char>(std::lround(std::pow(v, inv_gamma) * 255.f));
    };
    for (std::size_t i = 0; i < film.pixels.size(); ++i) {
        px[3 * i] = encode(film.pixels[i].r);
        px[3 * i + 1] = encode(film.pixels[i].g);
        px[3 * i + 2] = encode(film.pixels[i].b);
    }
    return px;
}
}  // namespace

std::string encode_png(const Film& film, float exposure, float gamma) {
    const std::vector<unsigned char> px = tone_map(film, exposure, gamma);
    std::string out;
    stbi_write_png_to_func(
        [](void* context, void* data, int size) {
            static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                                       std::size_t(size));
        },
        &out, film.width, film.height, 3, px.data(), film.width * 3);
    return out;
}

void write_png(const std::string& path, const Film& film, float exposure, float gamma) {
    write_preview(path, film, exposure, gamma, PreviewFormat::Png);
}

const EnumTable<PreviewFormat>& preview_formats() {
    static const EnumTable<PreviewFormat> t{{{"png", PreviewFormat::Png},
                                             {"jpg", PreviewFormat::Jpeg},
                                             {"jpeg", PreviewFormat::Jpeg},
                                             {"bmp", PreviewFormat::Bmp}}};
    return t;
}

std::string preview_extension(PreviewFormat f) {
    return std::string(".") + preview_formats().name(f);
}

void write_preview(const std::string& path, const Film& film, float exposure, float gamma,
                   PreviewFormat format) {
    const std::vector<unsigned char> px = tone_map(film, exposure, gamma);
    // Encoded in memory, then written by write_file_bytes, which checks every write: stb's own
    // file writers report success on a full disk.
    std::string bytes;
    auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                                   std::size_t(size));
    };
    const int w = film.width, h = film.height;
    int ok = 0;
    switch (format) {
        case PreviewFormat::Png:
            ok = stbi_write_png_to_func(append, &bytes, w, h, 3, px.data(), w * 3);
            break;
        case PreviewFormat::Jpeg:
            ok = stbi_write_jpg_to_func(append, &bytes, w, h, 3, px.data(), 95);
            break;
        case PreviewFormat::Bmp:
            ok = stbi_write_bmp_to_func(append, &bytes, w, h, 3, px.data());
            break;
    }
    if (!ok || bytes.empty()) throw std::runtime_error("cannot encode the preview " + path);
    write_file_bytes(path, bytes);
}

void write_difference_png(const std::string& path, const Film& a, const Film& b, float scale) {
    Film d(a.width, a.height);
    for (std::size_t i = 0; i < d.pixels.size(); ++i) {
        const RGB e = a.pixels[i] - b.pixels[i];
        const float m = (std::fabs(e.r) + std::fabs(e.g) + std::fabs(e.b)) / (3.f * scale);
        // Heat ramp: black -> red -> yellow -> white as the error grows to `scale`.
        const float x = std::clamp(m, 0.f, 1.f);
        d.pixels[i] = RGB{std::clamp(3.f * x, 0.f, 1.f), std::clamp(3.f * x - 1.f, 0.f, 1.f),
                          std::clamp(3.f * x - 2.f, 0.f, 1.f)};
    }
    write_png(path, d, 1.f, 1.f);
}

std::vector<uint8_t> read_png_mask(const std::string& path, int width, int height) {
    int w = 0, h = 0, c = 0;
    if (!stbi_info(path.c_str(), &w, &h, &c))
        throw InputError(path, 0, std::string("cannot read PNG: ") + stbi_failure_reason());
    check_claimed_size(path, w, h, 2048);
    unsigned char* data = stbi_load(path.c_str(), &w, &h, &c, 1);
    if (!data) throw InputError(path, 0, std::string("cannot read PNG: ") + stbi_failure_reason());
    std::vector<uint8_t> m(std::size_t(w) * std::size_t(h));
    for (std::size_t i = 0; i < m.size(); ++i) m[i] = data[i] != 0;
    stbi_image_free(data);
    if (w != width || h != height)
        throw InputError(path, 0,
                         "mask is " + std::to_string(w) + "x" + std::to_string(h) +
                             ", the images are " + std::to_string(width) + "x" +
                             std::to_string(height));
    return m;
}

}  // namespace foton
