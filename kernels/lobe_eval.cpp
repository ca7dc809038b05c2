// eval_lobes at SIMD width and its scalar twin: the forward pair and the reverse one through
// the same lobes.
#include "lobe_eval.h"

#include "diffuse_lobes.h"
#include "diffuse_lobes_scalar.h"

namespace foton::kern {

void eval_lobes(const ShadeTable& v, std::size_t n) {
    using namespace lanes;
    for (std::size_t i = 0; i < n; i += simd::kWidth) {
        const Lanes l{v, i};
        const V3 wo = l.in3(kDvWox), wi = l.in3(kDvLwx);
        V3 f, f_rev;
        FloatV pdf, pdf_rev;
        DiffuseLobes(l, wo).eval(wi, f, pdf);
        DiffuseLobes(l, wi).eval(wo, f_rev, pdf_rev);
        l.out3(kDvSvR, f);
        l.out(kDvNpdf, pdf);
        l.out(kDvPdfRev, pdf_rev);
    }
}

void eval_lobes_scalar(const ShadeTable& v, std::size_t n) {
    using namespace scalar;
    for (std::size_t i = 0; i < n; ++i) {
        const V3 wo = in3(v, kDvWox, i), wi = in3(v, kDvLwx, i);
        float pdf, pdf_rev;
        out3(v, kDvSvR, i, DiffuseLobes(v, i, wo).eval(wi, pdf));
        DiffuseLobes(v, i, wi).eval(wo, pdf_rev);
        v.col(kDvNpdf)[i] = pdf;
        v.col(kDvPdfRev)[i] = pdf_rev;
    }
}

}  // namespace foton::kern
