#pragma once
// Random vertex tables for the shading kernels' tests (test_diffuse_shade.cpp,
// test_glossy_shade.cpp, test_importance_shade.cpp): surfaces, throughputs, light samples and
// glossy lobes with every edge the engine produces.
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "engine/core/aligned.h"
#include "engine/core/math.h"
#include "engine/scene/bsdf.h"
#include "kernels/diffuse_shade.h"

namespace foton::test {

using namespace foton::kern;

struct Table {
    AlignedVector<float> data;
    std::size_t stride;
    explicit Table(std::size_t n)
        : data(std::size_t(kShadeColumns) *
               ((n + shade_width() - 1) / shade_width() * shade_width())),
          stride(data.size() / kShadeColumns) {}
    ShadeTable view() { return {data.data(), stride}; }
    float& at(uint32_t c, std::size_t i) { return data[c * stride + i]; }
    void set3(uint32_t c, std::size_t i, const Vec3& v) {
        at(c, i) = v.x;
        at(c + 1, i) = v.y;
        at(c + 2, i) = v.z;
    }
};

inline Vec3 random_unit(std::mt19937& g) {
    std::normal_distribution<float> n;
    for (;;) {
        const Vec3 v{n(g), n(g), n(g)};
        if (length(v) > 1e-3f) return normalize(v);
    }
}

// n random vertices; every fifth lane takes an edge value somewhere.
inline Table random_vertices(std::size_t n, uint32_t seed) {
    std::mt19937 g(seed);
    std::uniform_real_distribution<float> u01(0.f, 1.f), coord(-300.f, 300.f);
    Table t(n);
    for (std::size_t i = 0; i < n; ++i) {
        const bool edge = i % 5 == 0;
        const Vec3 p{coord(g), coord(g), coord(g)};
        const Vec3 ng = random_unit(g);
        // A shading normal leaning off the geometric one (sometimes past the horizon).
        const Vec3 ns = normalize(ng + random_unit(g) * (edge ? 1.2f : 0.3f));
        Vec3 wo = random_unit(g);
        if (dot(wo, ns) < 0.f && !edge) wo = -wo;
        t.set3(kDvPx, i, p);
        t.set3(kDvNgx, i, ng);
        t.set3(kDvNsx, i, ns);
        t.at(kDvEps, i) = 2e-5f * 300.f;
        t.set3(kDvWox, i, wo);
        t.set3(kDvRhoR, i, {u01(g), u01(g), edge && i % 3 == 0 ? 0.f : u01(g)});
        t.set3(kDvBetaR, i, {u01(g) * 2.f, u01(g), u01(g)});
        t.at(kDvEtaScale, i) = edge ? 2.25f : 1.f;
        // Lambert (A = 1, B = 0), or Oren–Nayar of some roughness on every third lane.
        const Lobe on = Lobe::oren_nayar(RGB{1.f}, 0.1f + 0.5f * u01(g));
        t.at(kDvOnA, i) = i % 3 == 2 ? on.on_a : 1.f;
        t.at(kDvOnB, i) = i % 3 == 2 ? on.on_b : 0.f;
        // The light sample: a point on a light, or a direction to one at infinity.
        const Vec3 q = p + random_unit(g) * (10.f + 200.f * u01(g));
        const bool infinite = i % 7 == 3;
        const Vec3 to = q - p;
        const float dist = length(to);
        t.at(kDvLightPdf, i) = i % 11 == 0 ? 0.f : 0.01f + u01(g);
        t.at(kDvLightFull, i) = i % 13 == 0 ? 1.f : 0.f;
        t.set3(kDvLwx, i, infinite ? random_unit(g) : to / dist);
        t.at(kDvLdist, i) = infinite ? kInfinity : dist;
        t.set3(kDvLpx, i, q);
        t.set3(kDvLnx, i, random_unit(g));
        t.set3(kDvLiR, i, {15.f * u01(g), 15.f, edge ? 0.f : 3.f});
        // Lanes whose surface the kernel makes: flat and smooth triangles, spheres.
        if (i % 4 != 0) {
            const float kind = float(i % 4);
            const float tt = 1.f + 100.f * u01(g);
            t.at(kDvSurface, i) = kind;
            t.at(kDvT, i) = tt;
            const Vec3 dir = -wo;
            if (kind == 3.f) {
                const Vec3 o = p - dir * tt;
                const float r = 1.f + 50.f * u01(g);
                t.set3(kDvOx, i, o);
                t.set3(kDvA0x, i, p - random_unit(g) * r);
                t.at(kDvA1x, i) = r;
            } else {
                const float bu = u01(g), bv = (1.f - bu) * u01(g);
                t.at(kDvU, i) = bu;
                t.at(kDvV, i) = bv;
                for (uint32_t c : {kDvA0x, kDvA1x, kDvA2x})
                    t.set3(c, i, p + random_unit(g) * (5.f + 40.f * u01(g)));
                // An axis-aligned triangle (a Cornell box wall): its normal has exact zeros,
                // whose signs pick the shading frame.
                if (i % 8 == 1) {
                    t.set3(kDvA0x, i, p);
                    t.set3(kDvA1x, i, p + Vec3{0.f, 10.f, 0.f});
                    t.set3(kDvA2x, i, p + Vec3{0.f, 0.f, 10.f});
                }
                for (uint32_t c : {kDvN0x, kDvN1x, kDvN2x}) t.set3(c, i, random_unit(g));
            }
        }
        // Every third lane a rectangle light for the kernel to sample (facing either way).
        if (i % 3 == 1) {
            const Vec3 e1 = random_unit(g) * (20.f + 80.f * u01(g));
            const Vec3 e2 = normalize(cross(e1, random_unit(g))) * (20.f + 80.f * u01(g));
            const Vec3 n_rect = normalize(cross(e1, e2));
            t.at(kDvLkind, i) = 1.f;
            t.set3(kDvLpx, i, q);
            t.set3(kDvLnx, i, i % 2 ? n_rect : -n_rect);
            t.set3(kDvLe1x, i, e1);
            t.set3(kDvLe2x, i, e2);
            t.at(kDvLarea, i) = length(cross(e1, e2));
            t.at(kDvLu0, i) = u01(g);
            t.at(kDvLu1, i) = u01(g);
            t.at(kDvLdist, i) = 0.f;
        }
        // Every sixth lane a triangle of an emissive mesh (one- or two-sided, facing either
        // way), with its own area or a whole mesh's in the density.
        if (i % 6 == 2) {
            const Vec3 e1 = random_unit(g) * (5.f + 60.f * u01(g));
            const Vec3 e2 = random_unit(g) * (5.f + 60.f * u01(g));
            const Vec3 n_tri = normalize(cross(e1, e2));
            t.at(kDvLkind, i) = kLightTriangle;
            t.set3(kDvLpx, i, q);
            t.set3(kDvLnx, i, i % 4 ? n_tri : -n_tri);
            t.set3(kDvLe1x, i, q + e1);  // a triangle's other corners
            t.set3(kDvLe2x, i, q + e2);
            t.at(kDvLarea, i) = 0.5f * length(cross(e1, e2)) * (i % 5 == 0 ? 7.f : 1.f);
            t.at(kDvLtwoSided, i) = i % 7 < 3 ? 1.f : 0.f;
            t.at(kDvLu0, i) = i % 11 == 0 ? 0.5f : u01(g);
            t.at(kDvLu1, i) = i % 11 == 0 ? 0.5f : u01(g);
            t.at(kDvLdist, i) = 0.f;
        }
        // Every sixth lane an emitting sphere sampled by its cone; some hold the point.
        if (i % 6 == 4) {
            const float r = 0.5f + 30.f * u01(g);
            t.at(kDvLkind, i) = kLightSphere;
            t.set3(kDvLpx, i, i % 5 == 0 ? p + random_unit(g) * (0.5f * r) : q);
            t.at(kDvLe1x, i) = r;
            t.at(kDvLu0, i) = i % 11 == 0 ? 0.f : u01(g);
            t.at(kDvLu1, i) = i % 13 == 0 ? 0.75f : u01(g);
            t.at(kDvLdist, i) = 0.f;
        }
        // The disc's centre and its diagonals, besides random numbers.
        const float u0 = i % 17 == 0 ? 0.5f : i % 19 == 0 ? 0.25f : u01(g);
        const float u1 = i % 17 == 0 ? 0.5f : i % 19 == 0 ? 0.25f : u01(g);
        t.at(kDvU0, i) = u0;
        t.at(kDvU1, i) = u1;
        t.at(kDvURoulette, i) = u01(g);
    }
    return t;
}

// Makes most lanes of `t` glossy (every seventh stays Lambertian or Oren–Nayar) and gives
// each lane's BSDF as the engine builds it: the diffuse lobe the table holds (rho, A, B)
// and a glossy lobe, before or after it.
inline void make_glossy(Table& t, std::size_t n, uint32_t seed, std::vector<Bsdf>& bsdfs) {
    std::mt19937 g(seed);
    std::uniform_real_distribution<float> u01(0.f, 1.f);
    bsdfs.assign(n, Bsdf{});
    for (std::size_t i = 0; i < n; ++i) {
        const RGB rho{t.at(kDvRhoR, i), t.at(kDvRhoG, i), t.at(kDvRhoB, i)};
        Lobe diffuse = Lobe::lambert(rho);
        if (t.at(kDvOnB, i) != 0.f) {
            diffuse.type = LobeType::OrenNayar;
            diffuse.on_a = t.at(kDvOnA, i);
            diffuse.on_b = t.at(kDvOnB, i);
        }
        t.at(kDvUChoice, i) = u01(g);
        if (i % 7 == 0) {
            t.at(kDvGlossKind, i) = 0.f;
            bsdfs[i].add(diffuse);
            continue;
        }
        Fresnel fr;
        if (i % 3 == 1) {
            fr.kind = FresnelKind::Conductor;
            fr.eta = RGB{0.2f + u01(g), 0.9f, 1.1f};
            fr.k = RGB{2.f + 2.f * u01(g), 2.5f, 2.f};
        } else if (i % 3 == 2) {
            fr.kind = FresnelKind::Dielectric;
            fr.ior = 1.3f + u01(g);
        }
        const RGB tint{0.3f + 0.7f * u01(g), 0.8f, 0.2f + 0.8f * u01(g)};
        Lobe glossy;
        switch (i % 6) {
            case 0:
                glossy = Lobe::phong(tint, 1.f + 500.f * u01(g) * u01(g));
                break;
            case 1:
                glossy = Lobe::microfacet(
                    tint, MicrofacetDistribution::beckmann(0.03f + 0.6f * u01(g)), fr);
                break;
            case 2: {
                const float e = 2.f + 800.f * u01(g) * u01(g);
                glossy = Lobe::microfacet(tint, MicrofacetDistribution::blinn(e), fr);
                break;
            }
            case 4:
                glossy = Lobe::microfacet(
                    tint,
                    MicrofacetDistribution::trowbridge_reitz(
                        0.02f + 0.8f * u01(g) * u01(g), i % 12 == 4 ? 0.3f : 0.02f + 0.8f * u01(g)),
                    fr);
                break;
            default:
                glossy = Lobe::microfacet(
                    tint,
                    MicrofacetDistribution::ashikhmin_shirley(1.f + 900.f * u01(g) * u01(g),
                                                              1.f + 900.f * u01(g) * u01(g)),
                    fr);
        }
        const bool alone = i % 11 == 4, first = i % 4 >= 2;
        if (first || alone) bsdfs[i].add(glossy);
        if (!alone) bsdfs[i].add(diffuse);
        if (!first && !alone) bsdfs[i].add(glossy);
        const int gi = first || alone ? 0 : 1;
        const MicrofacetKind mk = glossy.dist.kind;
        const bool alpha_kind =
            mk == MicrofacetKind::Beckmann || mk == MicrofacetKind::TrowbridgeReitz;
        t.at(kDvGlossKind, i) = glossy.type == LobeType::Phong          ? kGlossPhong
                                : mk == MicrofacetKind::Beckmann        ? kGlossBeckmann
                                : mk == MicrofacetKind::TrowbridgeReitz ? kGlossGgx
                                                                        : kGlossCosPower;
        t.set3(kDvGlossR, i, {tint.r, tint.g, tint.b});
        t.at(kDvGlossNu, i) = glossy.type == LobeType::Phong ? glossy.exponent
                              : alpha_kind                   ? glossy.dist.alpha
                                                             : glossy.dist.nu;
        t.at(kDvGlossNv, i) = glossy.type == LobeType::Phong          ? glossy.exponent
                              : mk == MicrofacetKind::Beckmann        ? glossy.dist.alpha
                              : mk == MicrofacetKind::TrowbridgeReitz ? glossy.dist.alpha_y
                                                                      : glossy.dist.nv;
        t.at(kDvDiffuseWeight, i) = alone ? 0.f : bsdfs[i].weight(1 - gi);
        t.at(kDvGlossWeight, i) = bsdfs[i].weight(gi);
        t.at(kDvGlossFirst, i) = gi == 0 ? 1.f : 0.f;
        if (alone) t.set3(kDvRhoR, i, {0.f, 0.f, 0.f});
        t.at(kDvFresnel, i) = fr.kind == FresnelKind::Conductor    ? 1.f
                              : fr.kind == FresnelKind::Dielectric ? 2.f
                                                                   : 0.f;
        t.at(kDvIor, i) = fr.ior;
        t.set3(kDvEtaR, i, {fr.eta.r, fr.eta.g, fr.eta.b});
        t.set3(kDvKR, i, {fr.k.r, fr.k.g, fr.k.b});
    }
}

inline uint32_t bits(float x) {
    uint32_t b;
    std::memcpy(&b, &x, 4);
    return b;
}

// A SIMD kernel's table `a` against its scalar twin's `b` over n lanes: lanes whose shadow or
// continuation validity differ, and bits that differ in the surface columns and in the rays
// (and values) the valid lanes make.
struct TwinComparison {
    std::size_t validity_mismatches = 0, bit_mismatches = 0, shadows = 0, nexts = 0;
    std::size_t first_bad_lane = ~std::size_t(0);
};

inline TwinComparison compare_twin(Table& a, Table& b, std::size_t n) {
    TwinComparison r;
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t before = r.validity_mismatches + r.bit_mismatches;
        if (a.at(kDvShadowValid, i) != b.at(kDvShadowValid, i) ||
            a.at(kDvNextValid, i) != b.at(kDvNextValid, i)) {
            ++r.validity_mismatches;
        } else {
            auto same = [&](uint32_t from, uint32_t to) {
                for (uint32_t c = from; c <= to; ++c)
                    if (bits(a.at(c, i)) != bits(b.at(c, i))) ++r.bit_mismatches;
            };
            same(kDvPx, kDvEps);
            if (a.at(kDvShadowValid, i) != 0.f) {
                ++r.shadows;
                same(kDvSox, kDvSvB);
            }
            if (a.at(kDvNextValid, i) != 0.f) {
                ++r.nexts;
                same(kDvNox, kDvNpdf);
            }
        }
        if (r.first_bad_lane == ~std::size_t(0) &&
            r.validity_mismatches + r.bit_mismatches > before)
            r.first_bad_lane = i;
    }
    return r;
}

}  // namespace foton::test
