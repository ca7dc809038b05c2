#include "gltf_inputs.h"

#include <stb/stb_image.h>
#include <tiny_gltf.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "engine/core/input_file.h"
#include "engine/film/image_io.h"

namespace foton {

namespace fs = std::filesystem;

std::size_t json_nesting_depth(std::string_view json) {
    std::size_t depth = 0, deepest = 0;
    bool in_string = false, escaped = false;
    for (const char c : json) {
        if (in_string) {
            if (escaped)
                escaped = false;
            else if (c == '\\')
                escaped = true;
            else if (c == '"')
                in_string = false;
            continue;
        }
        if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            deepest = std::max(deepest, ++depth);
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return deepest;
}

std::string_view glb_json_chunk(std::string_view bytes) {
    // 12-byte header (magic, version, length), then the first chunk: length, type, data.
    if (bytes.size() < 20 || bytes.substr(0, 4) != "glTF") return {};
    uint32_t length = 0;
    std::memcpy(&length, bytes.data() + 12, 4);
    if (bytes.substr(16, 4) != "JSON" || length > bytes.size() - 20) return {};
    return bytes.substr(20, length);
}

namespace {

// Why `path` may not be read for a model in `folder` ("" when it may).
std::string refusal(const std::string& path, const std::string& folder) {
    std::error_code ec;
    const fs::path real = fs::weakly_canonical(path, ec);
    if (ec) return "cannot resolve the path";
    const std::string r = real.string();
    if (r.compare(0, folder.size(), folder) != 0 ||
        (r.size() > folder.size() && r[folder.size()] != '/' && folder != "/"))
        return "outside the model's folder " + folder +
               " (glTF files may only name files beside "
               "or below them)";
    return input_file_problem(r, kMaxMeshFileBytes);
}

bool file_exists(const std::string& path, void*) {
    std::error_code ec;
    return fs::exists(path, ec);
}

std::string expand_nothing(const std::string& path, void*) {
    return path;
}

bool read_under_root(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                     void* user) {
    const GltfFileRoot& root = *static_cast<const GltfFileRoot*>(user);
    const std::string why = refusal(path, root.folder);
    if (!why.empty()) {
        if (err) *err = why;
        return false;
    }
    try {
        const std::string bytes = read_input_file(path, kMaxMeshFileBytes, "glTF buffer");
        out->assign(bytes.begin(), bytes.end());
        return true;
    } catch (const std::exception& e) {
        if (err) *err = e.what();
        return false;
    }
}

bool write_nothing(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err = "foton does not write glTF files";
    return false;
}

// The library's own decoder, once the image's header claims a size the limits allow (as
// check_claimed_size does for files: at most kMaxInputPixels, at most 2048 pixels per byte).
bool load_checked_image(tinygltf::Image* image, const int index, std::string* err,
                        std::string* warn, int req_width, int req_height,
                        const unsigned char* bytes, int size, void*) {
    int w = 0, h = 0, c = 0;
    if (size <= 0 || !stbi_info_from_memory(bytes, size, &w, &h, &c)) {
        if (err) *err += "image " + std::to_string(index) + ": not a PNG or JPEG image\n";
        return false;
    }
    const uint64_t pixels = uint64_t(std::max(w, 0)) * uint64_t(std::max(h, 0));
    if (w <= 0 || h <= 0 || pixels > kMaxInputPixels || pixels > uint64_t(size) * 2048) {
        if (err)
            *err += "image " + std::to_string(index) + ": its header claims " + std::to_string(w) +
                    "x" + std::to_string(h) + " pixels in " + std::to_string(size) +
                    " bytes (at most " + std::to_string(kMaxInputPixels) +
                    " pixels, and no more than the bytes can encode)\n";
        return false;
    }
    return tinygltf::LoadImageData(image, index, err, warn, req_width, req_height, bytes, size,
                                   nullptr);
}

}  // namespace

void guard_gltf_loader(tinygltf::TinyGLTF& loader, GltfFileRoot& root) {
    std::error_code ec;
    const fs::path folder = fs::weakly_canonical(root.folder.empty() ? "." : root.folder, ec);
    root.folder = ec ? root.folder : folder.string();
    tinygltf::FsCallbacks cb;
    cb.FileExists = file_exists;
    cb.ExpandFilePath = expand_nothing;
    cb.ReadWholeFile = read_under_root;
    cb.WriteWholeFile = write_nothing;
    cb.user_data = &root;
    loader.SetFsCallbacks(cb);
    loader.SetImageLoader(load_checked_image, nullptr);
}

}  // namespace foton
