#include "scene_list.h"

#include <algorithm>
#include <filesystem>
#include <set>

#include "engine/core/error.h"

namespace foton::app {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kMaxListedScenes = 10000;
constexpr int kMaxDepth = 8;

// The last `n` components of `p` ("a/scenes" for n = 2).
std::string tail(const fs::path& p, int n) {
    std::vector<std::string> parts;
    for (const fs::path& c : p) parts.push_back(c.string());
    std::string out;
    for (int i = std::max(0, int(parts.size()) - n); i < int(parts.size()); ++i)
        if (!parts[std::size_t(i)].empty() && parts[std::size_t(i)] != "/")
            out += (out.empty() ? "" : "/") + parts[std::size_t(i)];
    return out;
}

bool inside(const fs::path& file, const fs::path& root) {
    const auto [r, f] = std::mismatch(root.begin(), root.end(), file.begin(), file.end());
    return r == root.end();
}

}  // namespace

std::map<std::string, std::string> list_scenes(const std::vector<std::string>& roots) {
    return list_files(roots, {".xml", ".pbrt"});
}

std::map<std::string, std::string> list_files(const std::vector<std::string>& roots,
                                              const std::vector<std::string>& extensions) {
    std::vector<fs::path> real;
    for (const std::string& d : roots) {
        std::error_code ec;
        if (!fs::is_directory(d, ec)) throw InputError(d, 0, "not a directory of scenes");
        real.push_back(fs::canonical(d));
    }
    // Prefixes: the folder's name, longer where two roots share it.
    std::vector<std::string> prefix(real.size());
    for (int n = 1;; ++n) {
        std::set<std::string> seen, clash;
        for (std::size_t i = 0; i < real.size(); ++i) {
            prefix[i] = tail(real[i], n);
            if (!seen.insert(prefix[i]).second) clash.insert(prefix[i]);
        }
        if (clash.empty() || n > 64) break;
    }
    std::map<std::string, std::string> scenes;
    for (std::size_t i = 0; i < real.size(); ++i) {
        std::error_code ec;
        fs::recursive_directory_iterator it(real[i], fs::directory_options::skip_permission_denied,
                                            ec),
            end;
        for (; !ec && it != end; it.increment(ec)) {
            if (it.depth() >= kMaxDepth) it.disable_recursion_pending();
            const fs::path& p = it->path();
            const std::string ext = p.extension().string();
            std::error_code file_ec;
            if (std::find(extensions.begin(), extensions.end(), ext) == extensions.end() ||
                !it->is_regular_file(file_ec))
                continue;
            const fs::path target = fs::canonical(p, file_ec);
            if (file_ec || !inside(target, real[i])) continue;  // a symlink out of the root
            const std::string name = prefix[i] + "/" + fs::relative(p, real[i]).generic_string();
            scenes.emplace(name, p.string());
            if (scenes.size() >= kMaxListedScenes) return scenes;
        }
    }
    return scenes;
}

}  // namespace foton::app
