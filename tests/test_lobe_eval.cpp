// The lobe-pair kernel (kernels/lobe_eval.h) that VCM's connections and merges use: SIMD bit
// for bit equal to its scalar twin on random direction pairs over every lobe the diffuse
// kernel takes, and the twin's f(wo, wi), pdf(wo -> wi) and pdf(wi -> wo) equal to the
// engine's Bsdf::f and Bsdf::pdf up to the lobes' polynomial rounding.
#include <catch2/catch.hpp>
#include <cmath>

#include "engine/scene/bsdf.h"
#include "kernels/lobe_eval.h"
#include "shade_vertices.h"

using namespace foton;
using namespace foton::kern;
using test::bits;
using test::make_glossy;
using test::random_unit;
using test::random_vertices;
using test::Table;

namespace {

// Random pairs of local directions: most on one side, some across, some grazing.
void random_pairs(Table& t, std::size_t n, uint32_t seed) {
    std::mt19937 g(seed);
    for (std::size_t i = 0; i < n; ++i) {
        Vec3 wo = random_unit(g), wi = random_unit(g);
        if (i % 4 != 0) {
            wo.z = std::fabs(wo.z);
            wi.z = std::fabs(wi.z);
        }
        if (i % 37 == 0) wi = normalize(Vec3{wi.x, wi.y, 0.f});
        t.set3(kDvWox, i, wo);
        t.set3(kDvLwx, i, wi);
    }
}

}  // namespace

TEST_CASE("Lobe pairs: SIMD equals its scalar twin bit for bit", "[kernel][shade][fast]") {
    const std::size_t n = 4099;
    std::vector<Bsdf> bsdfs;
    Table a = random_vertices(n, 61);
    make_glossy(a, n, 62, bsdfs);
    random_pairs(a, n, 63);
    Table b = a;
    eval_lobes(a.view(), n);
    eval_lobes_scalar(b.view(), n);
    std::size_t mismatches = 0, nonzero = 0;
    for (std::size_t i = 0; i < n; ++i) {
        for (uint32_t c : {uint32_t(kDvSvR), uint32_t(kDvSvG), uint32_t(kDvSvB), uint32_t(kDvNpdf),
                           uint32_t(kDvPdfRev)})
            mismatches += bits(a.at(c, i)) != bits(b.at(c, i));
        nonzero += a.at(kDvNpdf, i) > 0.f;
    }
    CHECK(mismatches == 0);
    CHECK(nonzero > n / 2);
    CHECK(nonzero < n);
}

TEST_CASE("Lobe pairs: the twin's f and densities are the engine's Bsdf::f and Bsdf::pdf",
          "[kernel][shade][fast]") {
    const std::size_t n = 6000;
    std::vector<Bsdf> bsdfs;
    Table t = random_vertices(n, 71);
    make_glossy(t, n, 72, bsdfs);
    random_pairs(t, n, 73);
    eval_lobes_scalar(t.view(), n);
    const BsdfContext ctx{};
    std::size_t compared = 0, glossy = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 wo{t.at(kDvWox, i), t.at(kDvWoy, i), t.at(kDvWoz, i)};
        const Vec3 wi{t.at(kDvLwx, i), t.at(kDvLwy, i), t.at(kDvLwz, i)};
        const RGB f = bsdfs[i].f(wo, wi, ctx);
        const float pdf = bsdfs[i].pdf(wo, wi, ctx), pdf_rev = bsdfs[i].pdf(wi, wo, ctx);
        INFO("lane " << i << " kind " << t.at(kDvGlossKind, i) << " wo.z " << wo.z << " wi.z "
                     << wi.z);
        CHECK(t.at(kDvSvR, i) == Approx(f.r).epsilon(2e-3).margin(1e-6));
        CHECK(t.at(kDvSvG, i) == Approx(f.g).epsilon(2e-3).margin(1e-6));
        CHECK(t.at(kDvSvB, i) == Approx(f.b).epsilon(2e-3).margin(1e-6));
        CHECK(t.at(kDvNpdf, i) == Approx(pdf).epsilon(2e-3).margin(1e-6));
        CHECK(t.at(kDvPdfRev, i) == Approx(pdf_rev).epsilon(2e-3).margin(1e-6));
        compared += pdf > 0.f;
        glossy += pdf > 0.f && t.at(kDvGlossKind, i) != 0.f;
    }
    CHECK(compared > n / 2);
    CHECK(glossy > n / 3);
}
