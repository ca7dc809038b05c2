// The measured BRDF (engine/scene/measured_brdf.h, pbrt-v4's "measured"): a synthetic .bsdf
// file written from a Trowbridge-Reitz (GGX) surface with a constant reflectance, in the RGL
// layout (D and sigma over the unit square; per incident angle the visible-normal density,
// a flat luminance and constant spectra), reads back as the microfacet BRDF it describes,
// fr D / (4 sigma(wo) cos theta_i); its samples follow its density (chi-square) and carry
// f and pdf as evaluated; the pbrt-v4 importer reads it, renders it, and names bad files.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "chi_square.h"
#include "engine/core/error.h"
#include "engine/core/rng.h"
#include "engine/core/tensor_file.h"
#include "engine/scene/bsdf.h"
#include "engine/scene/measured_brdf.h"
#include "engine/scene/pbrt_loader.h"
#include "engine/transport/registry/render.h"
#include "engine/transport/volume/volpath.h"
#include "tensor_writer.h"
#include "test_util.h"

using namespace foton;

namespace {

constexpr float kAlpha = 0.4f, kReflectance = 0.8f;

float ggx_d(float cos_m) {
    if (cos_m <= 0.f) return 0.f;
    const float c2 = cos_m * cos_m, t2 = (1.f - c2) / c2, a2 = kAlpha * kAlpha;
    return a2 / (kPi * c2 * c2 * (a2 + t2) * (a2 + t2));
}

// The projected area of the microfacets seen from polar angle theta: cos (1 + Lambda).
float ggx_sigma(float theta) {
    const float c = std::cos(theta), t2 = (1.f - c * c) / std::max(c * c, 1e-8f);
    return c * (0.5f + 0.5f * std::sqrt(1.f + kAlpha * kAlpha * t2));
}

float u_to_theta(float u) {
    return u * u * 0.5f * kPi;
}

// The .bsdf file's bytes: isotropic (one phi_i), 16 incident angles to 85 degrees.
std::string synthetic_bsdf() {
    const int nt = 16, dx = 64, dy = 8, vx = 48, vy = 32, lx = 8, ly = 8;
    std::vector<float> theta_i(nt), ndf, sigma, vndf, lum, spectra;
    for (int i = 0; i < nt; ++i) theta_i[std::size_t(i)] = float(i) / (nt - 1) * 85.f * kPi / 180.f;
    for (int y = 0; y < dy; ++y)
        for (int x = 0; x < dx; ++x) {
            const float theta = u_to_theta(float(x) / (dx - 1));
            ndf.push_back(ggx_d(std::cos(theta)));
            sigma.push_back(ggx_sigma(theta));
        }
    for (int i = 0; i < nt; ++i) {
        const float ti = theta_i[std::size_t(i)];
        const Vec3 wo{std::sin(ti), 0.f, std::cos(ti)};
        for (int y = 0; y < vy; ++y)
            for (int x = 0; x < vx; ++x) {
                // The visible normals' density over the square: D_wo(wm) |d omega / d(u, v)|.
                const float u = float(x) / (vx - 1), tm = u_to_theta(u);
                const float pm = (2.f * float(y) / (vy - 1) - 1.f) * kPi;
                const Vec3 wm{std::sin(tm) * std::cos(pm), std::sin(tm) * std::sin(pm),
                              std::cos(tm)};
                vndf.push_back(std::max(0.f, dot(wo, wm)) * ggx_d(wm.z) / ggx_sigma(ti) * 2.f *
                               kPi * kPi * u * std::sin(tm));
            }
        for (int k = 0; k < lx * ly; ++k) lum.push_back(1.f);
        for (int k = 0; k < 2 * lx * ly; ++k) spectra.push_back(kReflectance);
    }
    const uint64_t n = uint64_t(nt);
    auto byte = [](const std::string& name, uint8_t v) {
        return test::TensorOut{name, TensorType::UInt8, {1}, std::string(1, char(v))};
    };
    return test::tensor_bytes(
        {byte("description", 0), byte("jacobian", 1), test::float_tensor("theta_i", {n}, theta_i),
         test::float_tensor("phi_i", {1}, {0.f}),
         test::float_tensor("wavelengths", {2}, {400.f, 700.f}),
         test::float_tensor("ndf", {dy, dx}, ndf), test::float_tensor("sigma", {dy, dx}, sigma),
         test::float_tensor("vndf", {1, n, vy, vx}, vndf),
         test::float_tensor("luminance", {1, n, ly, lx}, lum),
         test::float_tensor("spectra", {1, n, 2, ly, lx}, spectra)});
}

Vec3 direction(float theta, float phi) {
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

}  // namespace

TEST_CASE("measured BRDF: a synthetic GGX file reads back as its microfacet BRDF",
          "[measured][fast]") {
    test::TempDir dir;
    std::ofstream(dir.file("ggx.bsdf"), std::ios::binary) << synthetic_bsdf();
    const auto b = load_measured_brdf(dir.file("ggx.bsdf"));
    CHECK(b->isotropic);
    const Lobe l = Lobe::measured_brdf(b.get());
    const BsdfContext ctx{true, Transport::Radiance};
    float worst = 0.f;
    for (int i = 0; i < 400; ++i) {
        const Vec3 wo = direction(rng::uniform(9, 1, uint64_t(i), 0) * 1.2f,
                                  rng::uniform(9, 1, uint64_t(i), 1) * 2.f * kPi);
        const Vec3 wi = direction(rng::uniform(9, 1, uint64_t(i), 2) * 1.2f,
                                  rng::uniform(9, 1, uint64_t(i), 3) * 2.f * kPi);
        const Vec3 wm = normalize(wo + wi);
        const float want = kReflectance * ggx_d(wm.z) / (4.f * ggx_sigma(std::acos(wo.z)) * wi.z);
        const RGB f = lobe_f(l, wo, wi, ctx);
        if (want < 1e-3f) continue;
        worst = std::max(worst, std::fabs(f.g / want - 1.f));
        CHECK(f.r == Approx(f.b).epsilon(1e-3));  // a constant spectrum is grey
    }
    INFO("worst relative error of f " << worst);
    CHECK(worst < 0.04f);
    // Below the surface and across it: nothing.
    CHECK(lobe_f(l, {0, 0, 1}, {0, 0.6f, -0.8f}, ctx).is_black());
    // Samples follow the density and carry f and pdf as evaluated.
    for (const float theta_o : {0.3f, 1.0f}) {
        const Vec3 wo = direction(theta_o, 0.4f);
        test::ChiSquareSetup setup;
        setup.samples = 100000;
        float worst_f = 0.f, worst_pdf = 0.f;
        const auto r = test::chi_square(
            setup,
            [&](int i, Vec3& wi) {
                BsdfSample s;
                if (!lobe_sample(
                        l, wo, 0.5f,
                        {rng::uniform(10, 2, uint64_t(i), 0), rng::uniform(10, 2, uint64_t(i), 1)},
                        ctx, s))
                    return false;
                wi = s.wi;
                worst_pdf =
                    std::max(worst_pdf, std::fabs(s.pdf / lobe_pdf(l, wo, s.wi, ctx) - 1.f));
                worst_f = std::max(worst_f, std::fabs(s.f.g / lobe_f(l, wo, s.wi, ctx).g - 1.f));
                return true;
            },
            [&](const Vec3& wi) { return double(lobe_pdf(l, wo, wi, ctx)); });
        INFO("theta_o " << theta_o << ": " << r.summary() << ", f " << worst_f << ", pdf "
                        << worst_pdf);
        CHECK(r.p_value > 1e-3);
        CHECK(worst_f < 1e-3f);
        CHECK(worst_pdf < 1e-3f);
    }
}

TEST_CASE("measured BRDF: pbrt-v4's measured material renders, bad files at their name",
          "[measured][pbrt]") {
    test::TempDir dir;
    const std::string bytes = synthetic_bsdf();
    std::ofstream(dir.file("ggx.bsdf"), std::ios::binary) << bytes;
    std::ofstream(dir.file("half.bsdf"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    auto scene = [&](const std::string& file) {
        return parse_pbrt_scene(
            "LookAt 0 0 3  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n"
            "Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16\nWorldBegin\n"
            "LightSource \"infinite\" \"rgb L\" [1 1 1]\n"
            "Material \"measured\" \"string filename\" \"" +
                file +
                "\"\n"
                "Shape \"sphere\"\nMaterial \"measured\" \"string filename\" \"" +
                file +
                "\"\n"
                "Translate 3 0 0\nShape \"sphere\"\n",
            dir.file("s.pbrt"), dir.path().string());
    };
    TestScene s(scene("ggx.bsdf"));
    CHECK(s.measured_brdfs.size() == 1);  // read once for both materials
    std::vector<double> means;
    for (const char* integrator : {"path", "volpath", "volpath spectral"}) {
        s.render.integrator = std::string(integrator).substr(0, integrator[0] == 'p' ? 4 : 7);
        VolPathSettings own;
        own.spectral = std::string(integrator).find("spectral") != std::string::npos;
        s.render.own = own;
        const Film f = render_test(s, 64, 2, 3).film;
        double sum = 0.0;
        for (const RGB& p : f.pixels) {
            REQUIRE(p.is_finite());
            sum += p.g;
        }
        means.push_back(sum / double(f.pixels.size()));
    }
    INFO("path " << means[0] << ", volpath " << means[1] << ", spectral " << means[2]);
    // The spheres under a white sky: lit, below the sky's radiance of 1; a constant spectrum
    // reads the same in RGB and at any wavelengths.
    CHECK(means[0] > 0.3);
    CHECK(means[0] < 1.0);
    CHECK(means[1] == Approx(means[0]).epsilon(0.02));
    CHECK(means[2] == Approx(means[0]).epsilon(0.02));
    try {
        scene("half.bsdf");
        FAIL("no error");
    } catch (const InputError& e) {
        CHECK_THAT(e.what(), Catch::Contains("half.bsdf") && Catch::Contains("tensor file"));
    }
}

TEST_CASE("measured BRDF: anisotropic files need the whole azimuth, and orient the frame",
          "[measured][fast]") {
    // A small valid file: 2 incident angles, 2 x 3 grids, phi_i nodes as given.
    auto file = [](const std::vector<float>& phis) {
        const uint64_t np = phis.size(), nt = 2;
        std::vector<float> vndf, lum, spectra;
        for (uint64_t k = 0; k < np * nt; ++k) {
            for (float v : {1.f, 0.5f, 0.1f, 1.f, 0.5f, 0.1f}) vndf.push_back(v);
            for (int i = 0; i < 4; ++i) lum.push_back(1.f);
            for (int i = 0; i < 8; ++i) spectra.push_back(0.5f);
        }
        auto byte = [](const std::string& name, uint8_t v) {
            return test::TensorOut{name, TensorType::UInt8, {1}, std::string(1, char(v))};
        };
        return test::tensor_bytes(
            {byte("description", 0), byte("jacobian", 1),
             test::float_tensor("theta_i", {nt}, {0.f, 1.f}),
             test::float_tensor("phi_i", {np}, phis),
             test::float_tensor("wavelengths", {2}, {400.f, 700.f}),
             test::float_tensor("ndf", {2, 3}, {1.f, 0.8f, 0.2f, 1.f, 0.8f, 0.2f}),
             test::float_tensor("sigma", {2, 3}, {1.f, 1.1f, 1.3f, 1.f, 1.1f, 1.3f}),
             test::float_tensor("vndf", {np, nt, 2, 3}, vndf),
             test::float_tensor("luminance", {np, nt, 2, 2}, lum),
             test::float_tensor("spectra", {np, nt, 2, 2, 2}, spectra)});
    };
    const auto iso = measured_brdf_from(parse_tensor_file(file({0.f}), "iso.bsdf"));
    CHECK(iso->isotropic);
    CHECK_FALSE(Lobe::measured_brdf(iso.get()).anisotropic());
    const auto aniso = measured_brdf_from(parse_tensor_file(file({-kPi, 0.f, kPi}), "aniso.bsdf"));
    CHECK_FALSE(aniso->isotropic);
    CHECK(Lobe::measured_brdf(aniso.get()).anisotropic());
    try {
        (void)measured_brdf_from(parse_tensor_file(file({0.f, 1.f, kPi}), "half.bsdf"));
        FAIL("no error");
    } catch (const InputError& e) {
        CHECK_THAT(e.what(), Catch::Contains("half.bsdf") && Catch::Contains("2 pi"));
    }
}
