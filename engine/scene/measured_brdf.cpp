#include "measured_brdf.h"

#include "bsdf.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/core/colorimetry.h"
#include "engine/core/error.h"
#include "engine/core/input_file.h"
#include "engine/core/tensor_file.h"

namespace foton {

namespace {

// Polar angle from the pole, accurate near it too (acos of z is not).
float polar(const Vec3& w) {
    return std::atan2(std::sqrt(w.x * w.x + w.y * w.y), w.z);
}

float theta_to_u(float theta) {
    return std::sqrt(std::max(0.f, theta) * (2.f / kPi));
}
float phi_to_v(float phi) {
    return phi * (0.5f / kPi) + 0.5f;
}
float u_to_theta(float u) {
    return u * u * (0.5f * kPi);
}
float v_to_phi(float v) {
    return (2.f * v - 1.f) * kPi;
}

// The half vector's unit-square point (u, v), and the change of measure from it to the
// solid angle of wi (the reflection's 4 (wo . wm) times the square's 2 pi^2 u sin theta_m).
struct HalfVector {
    Point2 uv;
    float jacobian;
};
HalfVector half_vector(const Vec3& wo, const Vec3& wm, bool isotropic, float phi_o) {
    const float theta_m = polar(wm);
    const float phi_m = std::atan2(wm.y, wm.x);
    Point2 uv{theta_to_u(theta_m), phi_to_v(isotropic ? phi_m - phi_o : phi_m)};
    uv.y -= std::floor(uv.y);
    const float sin_m = std::sqrt(wm.x * wm.x + wm.y * wm.y);
    return {uv, 4.f * dot(wo, wm) * std::max(2.f * kPi * kPi * uv.x * sin_m, 1e-6f)};
}

// fr at sample point u of incident (phi_o, theta_o): at three wavelengths, or as sRGB.
RGB reflectance(const MeasuredBrdf& b, Point2 u, float phi_o, float theta_o, const float* lambda) {
    float v[3];
    for (int c = 0; c < 3; ++c) {
        const float p[3] = {phi_o, theta_o, lambda ? lambda[c] : float(c)};
        v[c] = std::max(0.f, (lambda ? b.spectra : b.rgb).eval(u, p));
    }
    return {v[0], v[1], v[2]};
}

}  // namespace

// What f and pdf share for a direction pair: wo and wi flipped to the upper side, the
// incident angles, the half vector's point on the square and the visible-normal warp's inverse
// there. False when the pair has no half vector on that side.
struct MeasuredBrdf::Pair {
    Vec3 wo, wi;
    float theta_o = 0.f, phi_o = 0.f;
    Point2 uv;
    float jacobian = 0.f;
    Warp2D::Result ui;
};

bool MeasuredBrdf::pair(const Vec3& wo_in, const Vec3& wi_in, Pair& q) const {
    if (wo_in.z * wi_in.z <= 0.f) return false;
    const float s = wo_in.z < 0.f ? -1.f : 1.f;
    q.wo = wo_in * s;
    q.wi = wi_in * s;
    const Vec3 sum = q.wo + q.wi;
    if (dot(sum, sum) == 0.f) return false;
    q.theta_o = polar(q.wo);
    q.phi_o = std::atan2(q.wo.y, q.wo.x);
    const HalfVector h = half_vector(q.wo, normalize(sum), isotropic, q.phi_o);
    q.uv = h.uv;
    q.jacobian = h.jacobian;
    const float param[2] = {q.phi_o, q.theta_o};
    q.ui = vndf.invert(h.uv, param);
    return true;
}

RGB MeasuredBrdf::f(const Vec3& wo, const Vec3& wi, const float* lambda) const {
    Pair q;
    if (!pair(wo, wi, q)) return RGB{0.f};
    const float area = sigma.eval({theta_to_u(q.theta_o), phi_to_v(q.phi_o)});
    if (!(area > 0.f)) return RGB{0.f};
    return reflectance(*this, q.ui.p, q.phi_o, q.theta_o, lambda) *
           (ndf.eval(q.uv) / (4.f * area * q.wi.z));
}

float MeasuredBrdf::pdf(const Vec3& wo, const Vec3& wi) const {
    Pair q;
    if (!pair(wo, wi, q)) return 0.f;
    const float param[2] = {q.phi_o, q.theta_o};
    return q.ui.pdf * luminance.eval(q.ui.p, param) / q.jacobian;
}

bool MeasuredBrdf::sample(const Vec3& wo_in, Point2 u, const float* lambda, Vec3& wi, RGB& f,
                          float& pdf) const {
    const float s = wo_in.z < 0.f ? -1.f : 1.f;
    const Vec3 wo = wo_in * s;
    const float theta_o = polar(wo), phi_o = std::atan2(wo.y, wo.x);
    const float param[2] = {phi_o, theta_o};
    const Warp2D::Result lum = luminance.sample(u, param);
    const Warp2D::Result m = vndf.sample(lum.p, param);
    const float theta_m = u_to_theta(m.p.x);
    const float phi_m = v_to_phi(m.p.y) + (isotropic ? phi_o : 0.f);
    const float sin_m = std::sin(theta_m);
    const Vec3 wm{sin_m * std::cos(phi_m), sin_m * std::sin(phi_m), std::cos(theta_m)};
    const float om = dot(wo, wm);
    wi = wm * (2.f * om) - wo;
    if (wi.z <= 0.f || om <= 0.f) return false;
    const float area = sigma.eval({theta_to_u(theta_o), phi_to_v(phi_o)});
    if (!(area > 0.f)) return false;
    f = reflectance(*this, lum.p, phi_o, theta_o, lambda) * (ndf.eval(m.p) / (4.f * area * wi.z));
    pdf = m.pdf * lum.pdf / (4.f * om * std::max(2.f * kPi * kPi * m.p.x * sin_m, 1e-6f));
    wi = wi * s;
    return pdf > 0.f;
}

namespace {

// Per wavelength node, the linear-sRGB colour of its hat function (the piecewise-linear
// interpolation's basis, the ends held constant) under D65: a spectrum's colour is then the
// sum of its values times these.
std::vector<RGB> node_colours(const std::vector<float>& lambda) {
    std::vector<RGB> w(lambda.size(), RGB{0.f});
    const float step = 0.25f;
    for (float l = 360.f + 0.5f * step; l < 830.f; l += step) {
        const RGB c = xyz_to_linear_srgb(cie_xyz(l)) * (d65_normalised(l) * step);
        const std::size_t k =
            std::size_t(std::upper_bound(lambda.begin(), lambda.end(), l) - lambda.begin());
        if (k == 0) {
            w.front() += c;
        } else if (k == lambda.size()) {
            w.back() += c;
        } else {
            const float t = (l - lambda[k - 1]) / (lambda[k] - lambda[k - 1]);
            w[k - 1] += c * (1.f - t);
            w[k] += c * t;
        }
    }
    return w;
}

}  // namespace

std::shared_ptr<const MeasuredBrdf> load_measured_brdf(const std::string& path) {
    return measured_brdf_from(read_tensor_file(path, kMaxMeshFileBytes));
}

std::shared_ptr<const MeasuredBrdf> measured_brdf_from(const TensorFile& t) {
    const std::string& path = t.path;
    auto fail = [&](const std::string& what) -> void { throw InputError(path, 0, what); };
    const TensorField &theta_i = t.field("theta_i", 1), &phi_i = t.field("phi_i", 1),
                      &ndf = t.field("ndf", 2), &sigma = t.field("sigma", 2),
                      &vndf = t.field("vndf", 4), &luminance = t.field("luminance", 4),
                      &spectra = t.field("spectra", 5), &wavelengths = t.field("wavelengths", 1);
    const uint64_t n_phi = phi_i.shape[0], n_theta = theta_i.shape[0],
                   n_lambda = wavelengths.shape[0];
    const auto& vs = vndf.shape;
    const auto& ls = luminance.shape;
    const auto& ss = spectra.shape;
    if (vs[0] != n_phi || vs[1] != n_theta || ls[0] != n_phi || ls[1] != n_theta ||
        ss[0] != n_phi || ss[1] != n_theta || ss[2] != n_lambda || ls[2] != ss[3] ||
        ls[3] != ss[4] || n_phi == 0 || n_theta == 0 || n_lambda == 0)
        fail(
            "a measured BRDF's fields do not agree in shape (vndf, luminance and spectra over "
            "phi_i, theta_i; spectra over the wavelengths)");
    for (const TensorField* f : {&ndf, &sigma, &vndf, &luminance, &spectra})
        if (f->shape[f->shape.size() - 1] < 2 || f->shape[f->shape.size() - 2] < 2)
            fail("a measured BRDF's grids must be at least 2 x 2");
    auto floats = [&](const TensorField& f, const char* name) {
        std::vector<float> v = f.floats(path, name);
        for (float x : v)
            if (!std::isfinite(x))
                fail(std::string("field '") + name + "' holds a non-finite value");
        return v;
    };
    const std::vector<float> phis = floats(phi_i, "phi_i"), thetas = floats(theta_i, "theta_i"),
                             lambdas = floats(wavelengths, "wavelengths");
    for (const std::vector<float>* axis : {&phis, &thetas, &lambdas})
        for (std::size_t i = 1; i < axis->size(); ++i)
            if (!((*axis)[i] > (*axis)[i - 1]))
                fail("phi_i, theta_i and wavelengths must increase");
    // Anisotropic data must cover the whole azimuth (pbrt-v4 reads no reduced symmetry).
    if (n_phi > 2 && std::fabs(phis.back() - phis.front() - 2.f * kPi) > 1e-3f)
        fail("anisotropic data must span phi_i over 2 pi (symmetry reductions are not read)");
    auto b = std::make_shared<MeasuredBrdf>();
    try {
        b->path = path;
        b->isotropic = n_phi <= 2;
        const int w = int(vs[3]), h = int(vs[2]);
        b->ndf = Warp2D(floats(ndf, "ndf").data(), int(ndf.shape[1]), int(ndf.shape[0]), {}, false,
                        false);
        b->sigma = Warp2D(floats(sigma, "sigma").data(), int(sigma.shape[1]), int(sigma.shape[0]),
                          {}, false, false);
        b->vndf = Warp2D(floats(vndf, "vndf").data(), w, h, {phis, thetas});
        b->luminance =
            Warp2D(floats(luminance, "luminance").data(), int(ls[3]), int(ls[2]), {phis, thetas});
        const std::vector<float> s = floats(spectra, "spectra");
        const int sw = int(ss[4]), sh = int(ss[3]);
        b->spectra = Warp2D(s.data(), sw, sh, {phis, thetas, lambdas}, false, false);
        // The same grids as linear sRGB: channel c of each (phi_i, theta_i) the spectra's sum with
        // the wavelength nodes' colours.
        const std::vector<RGB> colour = node_colours(lambdas);
        const std::size_t grid = std::size_t(sw) * std::size_t(sh);
        std::vector<float> rgb(n_phi * n_theta * 3 * grid, 0.f);
        for (std::size_t a = 0; a < n_phi * n_theta; ++a)
            for (std::size_t k = 0; k < n_lambda; ++k) {
                const float* in = s.data() + (a * n_lambda + k) * grid;
                const float weight[3] = {colour[k].r, colour[k].g, colour[k].b};
                for (int c = 0; c < 3; ++c) {
                    float* out = rgb.data() + (a * 3 + std::size_t(c)) * grid;
                    for (std::size_t i = 0; i < grid; ++i) out[i] += weight[c] * in[i];
                }
            }
        b->rgb = Warp2D(rgb.data(), sw, sh, {phis, thetas, {0.f, 1.f, 2.f}}, false, false);
    } catch (const std::invalid_argument& e) {
        fail(std::string("a measured BRDF's grid cannot be read: ") + e.what());
    }
    return b;
}

RGB measured_f(const Lobe& l, const Vec3& wo, const Vec3& wi) {
    return l.color * l.measured->f(wo, wi, l.lambda[0] > 0.f ? l.lambda : nullptr);
}

float measured_pdf(const Lobe& l, const Vec3& wo, const Vec3& wi) {
    return l.measured->pdf(wo, wi);
}

bool measured_sample(const Lobe& l, const Vec3& wo, Point2 u, BsdfSample& s) {
    RGB f;
    if (!l.measured->sample(wo, u, l.lambda[0] > 0.f ? l.lambda : nullptr, s.wi, f, s.pdf))
        return false;
    s.f = l.color * f;
    s.flags = kGlossy | kReflection;
    return true;
}

}  // namespace foton
