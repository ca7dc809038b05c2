#include "job_agreement.h"

#include <array>
#include <cstdio>
#include <fstream>
#include <iterator>

#include "engine/core/error.h"
#include "engine/core/hash.h"
#include "scene_flags.h"

namespace foton::app {

namespace {

std::string hex(uint64_t h) {
    char buf[20];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
    return buf;
}

template <class T>
uint64_t hash_vector(const std::vector<T>& v, uint64_t h) {
    return v.empty() ? h : fnv1a(v.data(), v.size() * sizeof(T), h);
}

// The file's bytes: a rank that read another version of the scene (another node's copy).
std::string file_hash(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return hex(fnv1a(bytes.data(), bytes.size()));
}

// The geometry as loaded: meshes read from other files on another node differ here even
// when the scene file is the same.
std::string geometry_hash(const Scene& scene) {
    uint64_t h = fnv1a(nullptr, 0);
    for (const TriangleMesh& m : scene.meshes) {
        h = hash_vector(m.positions, h);
        h = hash_vector(m.indices, h);
    }
    // Spheres and analytic shapes come from the scene file, whose bytes are compared.
    const uint64_t counts[2] = {scene.spheres.size(), scene.shapes.size()};
    return hex(fnv1a(counts, sizeof counts, h));
}

std::string text(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

Bytes to_bytes(const std::string& s) {
    Bytes b(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) b[i] = std::byte(s[i]);
    return b;
}

JobFingerprint parse(const Bytes& b) {
    // Lines of "key\tvalue\n".
    JobFingerprint lines;
    std::string s(reinterpret_cast<const char*>(b.data()), b.size());
    std::size_t at = 0;
    while (at < s.size()) {
        const std::size_t end = s.find('\n', at);
        const std::string line = s.substr(at, end - at);
        const std::size_t tab = line.find('\t');
        lines.push_back(
            {line.substr(0, tab), tab == std::string::npos ? "" : line.substr(tab + 1)});
        if (end == std::string::npos) break;
        at = end + 1;
    }
    return lines;
}

}  // namespace

JobFingerprint job_fingerprint(const std::string& scene_path, const RenderJob& job) {
    const Scene& scene = job.scene;
    const FilmSettings& film = scene.film;
    const RenderOptions& opt = job.options;
    std::string camera;
    for (const std::array<float, 16>& m :
         {scene.camera.world_to_camera(), scene.camera.world_to_ndc()})
        for (const float v : m) camera += text(v) + " ";
    return {
        {"scene file's bytes", file_hash(scene_path)},
        {"geometry", std::to_string(scene.meshes.size()) + " meshes, " +
                         std::to_string(scene.spheres.size()) + " spheres, " +
                         std::to_string(scene.shapes.size()) + " shapes (" + geometry_hash(scene) +
                         ")"},
        {"resolution", std::to_string(film.width) + "x" + std::to_string(film.height)},
        {"crop", std::to_string(film.x0) + "," + std::to_string(film.y0) + " of " +
                     std::to_string(film.full_width) + "x" + std::to_string(film.full_height)},
        {"camera", camera},
        {"integrator", job.settings.integrator},
        {"settings", settings_text(scene)},
        {"samples per pass", std::to_string(opt.spp)},
        {"passes", std::to_string(opt.max_passes)},
        {"time budget", text(opt.time_limit)},
        {"seed", std::to_string(opt.seed)},
        {"accelerator", accel_name(scene.accel)},
    };
}

void agree_on_job(const Cluster& ranks, const JobFingerprint& mine, const std::string& scene_path) {
    if (!ranks.distributed()) return;
    std::string s;
    for (const auto& [key, value] : mine) s += key + "\t" + value + "\n";
    const std::vector<Bytes> all = ranks.all_gather(to_bytes(s));
    const JobFingerprint first = parse(all[0]);
    for (std::size_t r = 1; r < all.size(); ++r) {
        const JobFingerprint other = parse(all[r]);
        for (std::size_t i = 0; i < first.size() || i < other.size(); ++i) {
            const std::string key = i < first.size() ? first[i].first : other[i].first;
            const std::string a = i < first.size() ? first[i].second : "(none)";
            const std::string b = i < other.size() ? other[i].second : "(none)";
            if (a == b) continue;
            throw InputError(scene_path, 0,
                             "MPI ranks disagree on the job: rank " + std::to_string(r) + " has " +
                                 key + " '" + b + "', rank 0 has '" + a +
                                 "' (every rank must render the same scene with the same "
                                 "settings)");
        }
    }
}

}  // namespace foton::app
