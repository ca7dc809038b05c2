#include "path_guide.h"

#include <algorithm>
#include <cmath>

namespace foton {

std::size_t PathGuide::slot(const Vec3& p, const Vec3& n) const {
    const Vec3 g = (p - origin_) * inv_cell_;
    const std::size_t x = std::size_t(std::clamp(int(g.x), 0, res_[0] - 1));
    const std::size_t y = std::size_t(std::clamp(int(g.y), 0, res_[1] - 1));
    const std::size_t z = std::size_t(std::clamp(int(g.z), 0, res_[2] - 1));
    // The axis the surface faces, with its sign: a corner's walls, and the two sides of a
    // thin panel, see different light.
    const float ax = std::fabs(n.x), ay = std::fabs(n.y), az = std::fabs(n.z);
    const int axis = ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
    const float s = axis == 0 ? n.x : (axis == 1 ? n.y : n.z);
    const std::size_t voxel = (z * std::size_t(res_[1]) + y) * std::size_t(res_[0]) + x;
    return voxel * 6 + std::size_t(axis * 2 + (s < 0.f));
}

void PathGuide::build(const PhotonMap& photons, uint8_t flags, const Bounds3& bounds,
                      const PathGuideSettings& settings) {
    bins_.clear();
    const Vec3 d = bounds.diagonal();
    const float longest = std::max({d.x, d.y, d.z, 1e-6f});
    const float cell = longest / float(std::clamp<uint32_t>(settings.cells, 1, kMaxCells));
    inv_cell_ = 1.f / cell;
    // Padded by half a cell: photons on the bounds' faces fall inside.
    origin_ = bounds.lo - Vec3{0.5f * cell, 0.5f * cell, 0.5f * cell};
    const float ext[3] = {d.x, d.y, d.z};
    for (int a = 0; a < 3; ++a)
        res_[a] = std::clamp(int(std::ceil(ext[a] * inv_cell_)) + 1, 1, int(kMaxCells) + 1);
    index_.assign(std::size_t(res_[0]) * std::size_t(res_[1]) * std::size_t(res_[2]) * 6, -1);
    // In photon order, one histogram per bin: the guide is the same for any thread count.
    std::vector<SphereHistogram> bins;
    for (std::size_t i = 0; i < photons.size(); ++i) {
        if (!(photons.flags(i) & flags)) continue;
        int32_t& b = index_[slot(photons.position(i), photons.normal(i))];
        if (b < 0) {
            b = int32_t(bins.size());
            bins.emplace_back().clear();
        }
        bins[std::size_t(b)].add(photons.incident(i), photons.power(i).luminance());
    }
    // Keep the bins with enough photons to say where light comes from, in the order they
    // were made; the others guide nothing (their vertices sample the BSDF).
    std::vector<int32_t> renumber(bins.size(), -1);
    for (std::size_t b = 0; b < bins.size(); ++b) {
        // A twentieth spread evenly: cells where a few photons happened not to land still
        // get some density (the BSDF half of the mixture covers the rest).
        if (bins[b].count() < settings.min_photons || !bins[b].finish(0.05f)) continue;
        renumber[b] = int32_t(bins_.size());
        bins_.push_back(bins[b]);
    }
    for (int32_t& b : index_)
        if (b >= 0) b = renumber[std::size_t(b)];
}

std::size_t PathGuide::memory_bytes() const {
    return bins_.size() * sizeof(SphereHistogram) + index_.size() * sizeof(int32_t);
}

int PathGuide::find(const Vec3& p, const Vec3& ng) const {
    return bins_.empty() ? -1 : index_[slot(p, ng)];
}

bool sample_mixture(const Bsdf& bsdf, const Vec3& wo, const warp::Frame& frame,
                    const BsdfContext& ctx, const GuideMixture& mix, float u_choice, Point2 u,
                    BsdfSample& bs, float& bsdf_pdf) {
    const float a = mix.alpha;
    if (u_choice < a) {
        float guide_pdf;
        const Vec3 wi_world = mix.guide->sample(u, guide_pdf);
        bs = {};
        bs.wi = frame.to_local(wi_world);
        bs.f = bsdf.f(wo, bs.wi, ctx);
        if (bs.f.is_black()) return false;
        bs.flags = uint8_t(kDiffuse | (bs.wi.z * wo.z > 0.f ? kReflection : kTransmission));
        bsdf_pdf = bsdf.pdf(wo, bs.wi, ctx);
        bs.pdf = a * guide_pdf + (1.f - a) * bsdf_pdf;
        return bs.pdf > 0.f;
    }
    const float uc = std::min((u_choice - a) / (1.f - a), 0x1.fffffep-1f);
    if (!bsdf.sample(wo, uc, u, ctx, bs)) return false;
    bsdf_pdf = bs.pdf;
    bs.pdf = (1.f - a) * bs.pdf + a * mix.guide->pdf(frame.to_world(bs.wi));
    return bs.pdf > 0.f;
}

}  // namespace foton
