#include "lobe_pairs.h"

#include <algorithm>

#include "kernels/lobe_eval.h"

namespace foton {

void LobePairs::evaluate(const KernelMaterials& km) {
    const std::size_t n = size();
    f.resize(n);
    pdf.resize(n);
    pdf_rev.resize(n);
    KernelLanes& L = lanes;
    for (std::size_t start = 0; start < n; start += KernelLanes::kLanes) {
        L.size = std::min(KernelLanes::kLanes, n - start);
        for (std::size_t k = 0; k < L.size; ++k) {
            const std::size_t r = start + k;
            L.put3(kern::kDvWox, k, wo[r]);
            L.put3(kern::kDvLwx, k, wi[r]);
            put_diffuse_material(L, k, km, material[r]);
        }
        kern::eval_lobes(L.table(), L.size);
        for (std::size_t k = 0; k < L.size; ++k) {
            const Vec3 v = L.get3(kern::kDvSvR, k);
            f[start + k] = RGB{v.x, v.y, v.z};
            pdf[start + k] = L.col(kern::kDvNpdf)[k];
            pdf_rev[start + k] = L.col(kern::kDvPdfRev)[k];
        }
    }
}

}  // namespace foton
