#include "importon_map.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "engine/core/rng.h"
#include "engine/core/rng_streams.h"
#include "engine/core/warp.h"
#include "engine/transport/common/surface.h"

namespace foton {

namespace {
constexpr uint64_t kImportonChunk = 4096;
// Cells with at least this share of the mean importance (over the cells importons reached)
// keep every photon: the visible surfaces are not all seen equally often, and thinning the
// less-seen ones would trade their noise for nothing.
constexpr float kFullShare = 0.25f;
}  // namespace

void ImportonMap::build(const Scene& scene, const Intersector& accel, const ImportonSettings& s,
                        uint64_t seed) {
    cells_.clear();
    recorded_ = 0;
    if (s.count == 0) return;
    bounds_ = scene.bounds();
    const Vec3 ext = bounds_.diagonal();
    const float pad = 1e-3f * std::max({ext.x, ext.y, ext.z, 1e-6f});
    bounds_.lo = bounds_.lo - Vec3{pad, pad, pad};
    bounds_.hi = bounds_.hi + Vec3{pad, pad, pad};
    const Vec3 size = bounds_.diagonal();
    // About 16 importons per reached cell when a tenth of the cells is reached, within
    // [8, 128] cells along the longest axis.
    const double target = std::clamp(double(s.count) / 1.6, 512.0, double(1u << 21));
    const double cell = std::cbrt(double(size.x) * size.y * size.z / target);
    for (int a = 0; a < 3; ++a) {
        res_[a] = std::clamp(int(std::ceil(size[a] / std::max(cell, 1e-30))), 1, 128);
        inv_cell_[a] = float(res_[a]) / size[a];
    }
    const std::size_t n = std::size_t(res_[0]) * std::size_t(res_[1]) * std::size_t(res_[2]);

    // The importons, a chunk per task, each listing the cells it counts; summed in chunk
    // order (integer counts: the map is the same for any thread count).
    const std::size_t chunks = std::size_t((s.count + kImportonChunk - 1) / kImportonChunk);
    std::vector<std::vector<uint32_t>> found(chunks);
    const float w = float(scene.film.width), h = float(scene.film.height);
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
        TraceCounters tc;
        std::vector<uint32_t>& out = found[c];
        const uint64_t end = std::min<uint64_t>(s.count, (c + 1) * kImportonChunk);
        for (uint64_t k = c * kImportonChunk; k < end; ++k) {
            auto u = [&](uint32_t dim) { return rng::uniform(seed, kImportonStream, k, dim); };
            Vec3 o, d;
            scene.camera.generate(u(0) * w, u(1) * h, {u(2), u(3)}, o, d);
            uint32_t diffuse = 0, specular = 0;
            for (uint32_t bounce = 0; bounce < 64; ++bounce) {
                Hit1 hit;
                if (!accel.intersect1({o.x, o.y, o.z, d.x, d.y, d.z, 0.f, kInfinity}, hit, tc))
                    break;
                const SurfacePoint sp =
                    surface_at(scene, hit.geom, hit.prim, hit.t, hit.u, hit.v, o, d);
                std::optional<Material> scratch;
                const Material& m = scene.material_at(hit.geom, sp.tex(), scratch);
                const uint32_t dim = 4 + 4 * bounce;
                if (m.bsdf.empty()) {  // an interface: pass through
                    o = offset_origin(sp, d);
                    continue;
                }
                if (m.bsdf.has_non_delta()) {
                    out.push_back(uint32_t(cell_of(sp.p)));
                    if (diffuse++ >= s.diffuse_bounces) break;
                    // On where a gather ray from here would look: cosine about the side
                    // the importon came from.
                    const Vec3 n = dot(sp.ng, d) < 0.f ? sp.ng : -sp.ng;
                    d = warp::Frame(n).to_world(warp::cosine_hemisphere({u(dim), u(dim + 1)}));
                    o = offset_origin(sp, d);
                    continue;
                }
                if (specular++ >= s.max_specular) break;
                const warp::Frame frame = sp.frame();
                BsdfSample bs;
                const BsdfContext ctx{sp.front_face, Transport::Radiance};
                if (!m.bsdf.sample(frame.to_local(-d), u(dim + 2), {u(dim), u(dim + 1)}, ctx, bs))
                    break;
                d = frame.to_world(bs.wi);
                o = offset_origin(sp, d);
            }
        }
    });
    std::vector<uint32_t> count(n, 0);
    for (const std::vector<uint32_t>& f : found)
        for (const uint32_t i : f) ++count[i], ++recorded_;

    // Dilate: each cell takes the largest count of its 3 x 3 x 3 neighbourhood.
    cells_.assign(n, 0.f);
    double sum = 0.0;
    std::size_t reached = 0;
    for (int z = 0; z < res_[2]; ++z)
        for (int y = 0; y < res_[1]; ++y)
            for (int x = 0; x < res_[0]; ++x) {
                uint32_t m = 0;
                for (int dz = std::max(z - 1, 0); dz <= std::min(z + 1, res_[2] - 1); ++dz)
                    for (int dy = std::max(y - 1, 0); dy <= std::min(y + 1, res_[1] - 1); ++dy)
                        for (int dx = std::max(x - 1, 0); dx <= std::min(x + 1, res_[0] - 1); ++dx)
                            m = std::max(m, count[(std::size_t(dz) * res_[1] + dy) * res_[0] + dx]);
                cells_[(std::size_t(z) * res_[1] + y) * res_[0] + x] = float(m);
                if (m > 0) sum += m, ++reached;
            }
    min_probability_ = std::clamp(s.min_probability, 1e-4f, 1.f);
    const float full = reached ? kFullShare * float(sum / double(reached)) : 1.f;
    for (float& c : cells_) c = std::clamp(c / full, min_probability_, 1.f);
}

std::size_t ImportonMap::cell_of(const Vec3& p) const {
    int c[3];
    for (int a = 0; a < 3; ++a)
        c[a] = std::clamp(int((p[a] - bounds_.lo[a]) * inv_cell_[a]), 0, res_[a] - 1);
    return (std::size_t(c[2]) * std::size_t(res_[1]) + std::size_t(c[1])) * std::size_t(res_[0]) +
           std::size_t(c[0]);
}

float ImportonMap::store_probability(const Vec3& p) const {
    return cells_.empty() ? 1.f : cells_[cell_of(p)];
}

float ImportonMap::full_fraction() const {
    if (cells_.empty()) return 1.f;
    std::size_t full = 0;
    for (const float c : cells_) full += c >= 1.f;
    return float(full) / float(cells_.size());
}

}  // namespace foton
