#pragma once
// A batch of BSDF evaluations at given direction pairs, for the strategies that join two
// vertices they did not sample between (VCM's connections and merges): each request is a
// material the diffuse kernel takes and two local directions; one `evaluate` runs them all
// through kern::eval_lobes, 64 lanes a call, and leaves f(wo, wi), pdf(wo -> wi) and
// pdf(wi -> wo) per request.
#include <cstdint>
#include <vector>

#include "engine/core/math.h"
#include "engine/core/rgb.h"
#include "kernel_materials.h"

namespace foton {

struct LobePairs {
    // The requests.
    std::vector<uint32_t> material;
    std::vector<Vec3> wo, wi;
    // The results, by request.
    std::vector<RGB> f;
    std::vector<float> pdf, pdf_rev;
    KernelLanes lanes;

    void clear() {
        material.clear();
        wo.clear();
        wi.clear();
    }
    std::size_t size() const { return material.size(); }
    // Queues f and both densities of `m` (a Diffuse kernel material) at local wo, wi; the
    // request's index.
    uint32_t add(uint32_t m, const Vec3& o, const Vec3& i) {
        material.push_back(m);
        wo.push_back(o);
        wi.push_back(i);
        return uint32_t(material.size() - 1);
    }
    void evaluate(const KernelMaterials& km);
};

}  // namespace foton
