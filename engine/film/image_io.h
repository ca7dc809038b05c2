#pragma once
// Image output. Every writer goes through a temporary file in the target directory and a
// rename, so a failed or interrupted render never leaves a truncated image under the
// requested name.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "aov.h"
#include "engine/core/params.h"
#include "file_write.h"
#include "film.h"

namespace foton {

using ImageAttributes = std::vector<std::pair<std::string, std::string>>;

// The standard attributes pbrt-v4 writes that tools read (tev, OpenImageIO): the render
// time and samples per pixel (each left out when negative).
struct ExrRenderInfo {
    float render_seconds = -1.f;
    int samples_per_pixel = -1;
    // pbrt-v4's MSE: the mean squared error against a reference (over pixels and channels).
    std::optional<float> mse;
    // OpenEXR's worldToCamera and worldToNDC (Camera::world_to_camera/world_to_ndc).
    std::optional<std::array<float, 16>> world_to_camera, world_to_ndc;
    // A crop window: the film is the data window at (x0, y0) of a display window of
    // display_width x display_height (0: the film's own size).
    int x0 = 0, y0 = 0, display_width = 0, display_height = 0;
    // The samples each pixel averages, written as a UINT channel `samples` when given (one per
    // film pixel): where they differ (adaptive sampling, an interrupted pass) it says which
    // pixels hold how much, and 0 marks the ones no sample reached.
    const std::vector<uint32_t>* samples = nullptr;
    // Extra float channels (aov.h), one film pixel each, when given.
    const std::vector<AovLayer>* layers = nullptr;
};

// Linear float RGB OpenEXR (Rec. 709 / sRGB primaries, written as chromaticities) with string
// header attributes and, when given, the standard render attributes.
void write_exr(const std::string& path, const Film& film, const ImageAttributes& attrs = {},
               const ExrRenderInfo& info = {});
// The same file's bytes, in memory (`name` for OpenEXR's messages).
std::string encode_exr(const std::string& name, const Film& film, const ImageAttributes& attrs = {},
                       const ExrRenderInfo& info = {});
// The string, float and int attributes of an OpenEXR file's header, as text.
ImageAttributes read_exr_attributes(const std::string& path);
// Reads the R, G, B channels of an OpenEXR file as float. Throws InputError.
Film read_exr(const std::string& path);
// Reads the named channels of an OpenEXR file as float (a UINT channel converted), channel by
// channel per pixel, row-major over the data window. Throws InputError naming a channel the
// file lacks.
std::vector<float> read_exr_channels(const std::string& path, const std::vector<std::string>& names,
                                     int& width, int& height);

// Images read (EXR, textures, masks) are at most this many pixels (16384 x 16384).
inline constexpr uint64_t kMaxInputPixels = uint64_t(1) << 28;
// Refuses, before any pixel memory is taken, an image whose header claims width x height
// beyond kMaxInputPixels or beyond what its file could encode: no format foton reads packs
// more than `pixels_per_byte` pixels into a byte of file (deflate's ratio is at most 1032:1
// of bytes, and a pixel is at least one byte), so a 45-byte PNG claiming 16384^2 is a corrupt
// or hostile header, not an image.
void check_claimed_size(const std::string& path, int width, int height, uint64_t pixels_per_byte);
// 8-bit preview: value = clamp(exposure * L, 0, 1)^(1 / gamma).
void write_png(const std::string& path, const Film& film, float exposure, float gamma);
// The same preview as PNG, JPEG (quality 95) or BMP: the formats the ray-tracing thesis'
// program saved.
enum class PreviewFormat { Png, Jpeg, Bmp };
// png, jpg (alias jpeg), bmp: each format's first name is its file extension.
const EnumTable<PreviewFormat>& preview_formats();
std::string preview_extension(PreviewFormat f);  // ".png", ".jpg", ".bmp"
void write_preview(const std::string& path, const Film& film, float exposure, float gamma,
                   PreviewFormat format);
// The same preview as PNG file contents, in memory.
std::string encode_png(const Film& film, float exposure, float gamma);
// A mask from a PNG of the given size: pixels that are not black count. Throws InputError.
std::vector<uint8_t> read_png_mask(const std::string& path, int width, int height);
// False-colour PNG of |a - b| per pixel (mean over channels): black at 0 through red and
// yellow to white at `scale`.
void write_difference_png(const std::string& path, const Film& a, const Film& b, float scale);

}  // namespace foton
