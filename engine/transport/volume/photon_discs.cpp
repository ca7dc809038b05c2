#include "photon_discs.h"

#include <cmath>

namespace foton {

void PhotonDiscs::build(const PhotonMap& photons, float r,
                        const kern::BvhBuildParams::ParallelInvoke& parallel) {
    photons_ = &photons;
    r_ = r;
    std::vector<kern::PrimRef> refs;
    refs.reserve(photons.size());
    for (std::size_t i = 0; i < photons.size(); ++i) {
        const Vec3 p = photons.position(i);
        if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) continue;
        kern::PrimRef ref{};
        ref.lo[0] = p.x - r;
        ref.lo[1] = p.y - r;
        ref.lo[2] = p.z - r;
        ref.hi[0] = p.x + r;
        ref.hi[1] = p.y + r;
        ref.hi[2] = p.z + r;
        ref.id = uint32_t(i);
        refs.push_back(ref);
    }
    kern::BvhBuildParams params;
    params.max_leaf = 8;
    params.leaf_block = 1;  // photons are tested one at a time
    params.parallel = parallel;
    bvh_ = kern::build_binary_bvh(refs, params);
}

}  // namespace foton
