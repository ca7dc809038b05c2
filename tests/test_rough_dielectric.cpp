// The rough dielectric interface (engine/scene/rough_dielectric.h): chi-square tests of its
// sampling against its pdf over the whole sphere (reflection and transmission, entering and
// leaving the glass, isotropic and anisotropic roughness), the adjoint relation between
// radiance and importance transport, energy (at most one in importance transport, close to
// one when smooth), and the smooth limit: reflection chosen with the delta dielectric's
// Fresnel probability.
#include <catch2/catch.hpp>
#include <tuple>

#include "chi_square.h"
#include "engine/core/optics.h"
#include "engine/core/rng.h"
#include "engine/scene/bsdf.h"

using namespace foton;

namespace {

Vec3 direction(float theta_deg, float phi) {
    const float t = theta_deg * kPi / 180.f;
    return {std::sin(t) * std::cos(phi), std::sin(t) * std::sin(phi), std::cos(t)};
}

Bsdf glass(float ax, float ay, float ior = 1.5f) {
    Bsdf b;
    b.add(Lobe::rough_dielectric(ior, MicrofacetDistribution::trowbridge_reitz(ax, ay), RGB{1.f},
                                 RGB{1.f}));
    return b;
}

}  // namespace

TEST_CASE("rough dielectric: sampling has the density its pdf reports, both sides",
          "[bsdf][rough_dielectric]") {
    const std::tuple<float, float> roughness[] = {
        {0.1f, 0.1f}, {0.4f, 0.4f}, {0.9f, 0.9f}, {0.1f, 0.5f}};
    const float incidence[] = {0.f, 40.f, 75.f};
    const int tests = int(std::size(roughness) * std::size(incidence) * 2);
    const double alpha = 1.0 - std::pow(1.0 - 0.01, 1.0 / tests);  // Sidak, 1 % overall
    int index = 0;
    for (const auto& [ax, ay] : roughness) {
        const Bsdf b = glass(ax, ay);
        for (float theta : incidence) {
            for (const bool front : {true, false}) {
                ++index;
                const Vec3 wo = direction(theta, 0.4f);
                const BsdfContext ctx{front, Transport::Radiance};
                test::ChiSquareSetup setup;
                setup.samples = 100000;
                setup.axis = -wo;  // straight through: the transmitted lobe's neighbourhood
                const auto r = test::chi_square(
                    setup,
                    [&](int i, Vec3& wi) {
                        BsdfSample s;
                        const uint64_t key = 1000 + uint64_t(index);
                        if (!b.sample(wo, rng::uniform(12, key, uint64_t(i), 0),
                                      {rng::uniform(12, key, uint64_t(i), 1),
                                       rng::uniform(12, key, uint64_t(i), 2)},
                                      ctx, s))
                            return false;
                        wi = s.wi;
                        return true;
                    },
                    [&](const Vec3& wi) { return double(b.pdf(wo, wi, ctx)); });
                INFO("alpha " << ax << "/" << ay << " at " << theta << " deg, "
                              << (front ? "entering" : "leaving") << ": " << r.summary());
                CHECK(r.p_value > alpha);
                CHECK(r.expected_total == Approx(r.observed_total).margin(0.01));
            }
        }
    }
}

TEST_CASE("rough dielectric: radiance and importance transport are each other's adjoint",
          "[bsdf][rough_dielectric]") {
    const Bsdf b = glass(0.3f, 0.2f);
    int transmitted = 0, reflected = 0;
    for (int i = 0; i < 2000; ++i) {
        const Vec3 wo = normalize(direction(85.f * rng::uniform(13, 0, uint64_t(i), 0),
                                            6.f * rng::uniform(13, 0, uint64_t(i), 1)));
        const Vec3 w = direction(179.f * rng::uniform(13, 0, uint64_t(i), 2),
                                 6.f * rng::uniform(13, 0, uint64_t(i), 3));
        for (const bool front : {true, false}) {
            // f*(wo, wi) = f(wi, wo) in the same frame: a first direction below the surface
            // is in the other medium.
            const RGB radiance = b.f(wo, w, {front, Transport::Radiance});
            const bool across = w.z < 0.f;
            const RGB adjoint = b.f(w, wo, {front, Transport::Importance});
            INFO("wo " << wo.x << " " << wo.y << " " << wo.z << " wi " << w.x << " " << w.y << " "
                       << w.z << " front " << front);
            CHECK(radiance.g == Approx(adjoint.g).epsilon(1e-3).margin(1e-6));
            if (radiance.g > 0.f) (across ? transmitted : reflected)++;
        }
    }
    CHECK(transmitted > 500);
    CHECK(reflected > 500);
}

TEST_CASE("rough dielectric: energy at most one, near one when smooth, F's choice in the limit",
          "[bsdf][rough_dielectric]") {
    for (const float a : {0.02f, 0.3f, 0.8f}) {
        const Bsdf b = glass(a, a);
        for (const float theta : {0.f, 50.f, 80.f}) {
            for (const bool front : {true, false}) {
                const Vec3 wo = direction(theta, 0.f);
                const BsdfContext ctx{front, Transport::Importance};
                const int n = 100000;
                double sum = 0.0;
                int refl = 0;
                for (int i = 0; i < n; ++i) {
                    BsdfSample s;
                    if (!b.sample(wo, rng::uniform(14, 0, uint64_t(i), 0),
                                  {rng::uniform(14, 0, uint64_t(i), 1),
                                   rng::uniform(14, 0, uint64_t(i), 2)},
                                  ctx, s))
                        continue;
                    sum += double(s.f.g) * std::fabs(s.wi.z) / s.pdf;
                    refl += (s.flags & kReflection) != 0;
                }
                const double albedo = sum / n;
                INFO("alpha " << a << " at " << theta << " deg, front " << front << ": albedo "
                              << albedo << ", reflected " << double(refl) / n);
                CHECK(albedo <= 1.0 + 1e-3);
                // Single scattering keeps nearly all of a smooth interface's energy.
                if (a == 0.02f) {
                    CHECK(albedo > 0.97);
                    const float F = front ? fresnel_dielectric(wo.z, 1.f, 1.5f)
                                          : fresnel_dielectric(wo.z, 1.5f, 1.f);
                    CHECK(double(refl) / n == Approx(F).margin(0.02));
                }
            }
        }
    }
}
