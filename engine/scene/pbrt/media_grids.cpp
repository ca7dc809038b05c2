// The grids of pbrt-v4's grid media (uniformgrid, rgbgrid, nanovdb) as foton's: density and
// RGB grids over the box p0-p1, or a VDB file's grid, placed by the transform current at
// MakeNamedMedium (scales and translations only: foton's grids are axis-aligned in the world).
#include <algorithm>

#include "engine/scene/vdb_file.h"
#include "importer.h"
#include "spectrum.h"

namespace foton::pbrt {

namespace {

// pbrt-v4 leaves an rgbgrid's Le unnormalised, where homogeneous and uniformgrid media (and
// lights) divide an RGB emission by its illuminant's luminance, the integral of the CIE Y
// curve over the standard illuminant scaled to CIE_Y_integral: so an rgbgrid glows that many
// times brighter for the same rgb values. foton multiplies by it to render what pbrt-v4 does.
constexpr float kCieYIntegral = 106.856895f;

}  // namespace

int Importer::grid_samples(const Token& t, const std::string& what, const ParamList& p, int n[3]) {
    n[0] = p.integer("nx", 1);
    n[1] = p.integer("ny", 1);
    n[2] = p.integer("nz", 1);
    if (n[0] < 1 || n[1] < 1 || n[2] < 1) fail(t, what + ": nx, ny and nz must be positive");
    const uint64_t count = uint64_t(n[0]) * uint64_t(n[1]) * uint64_t(n[2]);
    if (count > (uint64_t(1) << 28)) fail(t, what + ": a grid has at most 2^28 samples");
    return int(count);
}

// The box p0-p1 (default the unit cube) in the world.
Bounds3 Importer::grid_box(const Token& t, const std::string& what, const ParamList& p) {
    const std::vector<Vec3> p0 = p.triples("p0"), p1 = p.triples("p1");
    const Vec3 a = p0.empty() ? Vec3{0, 0, 0} : p0[0], b = p1.empty() ? Vec3{1, 1, 1} : p1[0];
    const Affine& xf = gs_.ctm;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (i != j && xf.m[i][j] != 0.f)
                fail(t, what +
                            ": a grid medium placed by a rotation is not supported (scales "
                            "and translations only)");
    Bounds3 box;
    box.extend(xf.point(a));
    box.extend(xf.point(b));
    const Vec3 e = box.diagonal();
    if (!(e.x > 0.f && e.y > 0.f && e.z > 0.f)) fail(t, what + ": the box p0-p1 is empty");
    return box;
}

// pbrt-v4's uniformgrid: "density" nx x ny x nz values (x fastest) over the box p0-p1.
std::shared_ptr<const DensityGrid> Importer::uniform_grid(const Token& t, const std::string& what,
                                                          const ParamList& p) {
    int n[3];
    const int count = grid_samples(t, what, p, n);
    std::vector<float> density = p.reals("density");
    if (density.size() != std::size_t(count))
        fail(t, what + ": \"density\" has " + std::to_string(density.size()) +
                    " values, nx * ny * nz is " + std::to_string(count));
    for (float v : density)
        if (!(v >= 0.f && v < 1e12f))
            fail(t, what + ": density values must be non-negative and below 1e12");
    return std::make_shared<const DensityGrid>(n[0], n[1], n[2], std::move(density),
                                               grid_box(t, what, p));
}

// A uniformgrid's Le is scaled by its "Lescale" grid (nx x ny x nz values), or without one by
// a single sample of 1 in the box's centre: pbrt-v4's default, which fades the emission
// trilinearly towards the faces (to an eighth at the corners); foton does the same.
std::shared_ptr<const DensityGrid> Importer::emission_scale_grid(const Token& t,
                                                                 const std::string& what,
                                                                 const ParamList& p,
                                                                 const DensityGrid& density) {
    std::vector<float> s = p.reals("Lescale");
    if (s.empty())
        return std::make_shared<const DensityGrid>(1, 1, 1, std::vector<float>{1.f}, density.box());
    const std::size_t count =
        std::size_t(density.nx()) * std::size_t(density.ny()) * std::size_t(density.nz());
    if (s.size() != count)
        fail(t, what + ": \"Lescale\" has " + std::to_string(s.size()) +
                    " values, nx * ny * nz is " + std::to_string(count));
    for (float v : s)
        if (!(v >= 0.f && v < 1e12f))
            fail(t, what + ": Lescale values must be non-negative and below 1e12");
    return std::make_shared<const DensityGrid>(density.nx(), density.ny(), density.nz(),
                                               std::move(s), density.box());
}

// A uniformgrid's "temperature" array (nx x ny x nz, as "density"): it glows as the
// peak-normalised blackbody at (T - "temperatureoffset") x "temperaturescale" kelvin, scaled
// by the "Lescale" grid (or pbrt-v4's single centre sample), where it absorbs.
void Importer::uniform_temperature(const Token& t, const std::string& what, const ParamList& p,
                                   Medium& m) {
    std::vector<float> kelvin = p.reals("temperature");
    const DensityGrid& d = *m.density;
    const std::size_t count = std::size_t(d.nx()) * std::size_t(d.ny()) * std::size_t(d.nz());
    if (kelvin.size() != count)
        fail(t, what + ": \"temperature\" has " + std::to_string(kelvin.size()) +
                    " values, nx * ny * nz is " + std::to_string(count));
    for (float v : kelvin)
        if (!(v >= 0.f && v < 1e12f))
            fail(t, what + ": temperatures must be non-negative and below 1e12");
    m.temperature =
        std::make_shared<const DensityGrid>(d.nx(), d.ny(), d.nz(), std::move(kelvin), d.box());
    m.temperature_offset = p.real("temperatureoffset", p.real("temperaturecutoff", 0.f));
    m.temperature_scale = p.real("temperaturescale", 1.f);
    m.le_scale = emission_scale_grid(t, what, p, d);
    m.le_factor = 1.f;
    const float hottest = (m.temperature->max_value() - m.temperature_offset) * m.temperature_scale;
    m.blackbody = std::make_shared<const BlackbodyTable>(blackbody_emission_rgb, hottest);
}

// pbrt-v4's rgbgrid: "rgb sigma_a", "rgb sigma_s" and "rgb Le" arrays of nx x ny x nz values
// (a missing coefficient is 1 throughout the box; Le needs sigma_a), the coefficients times
// "scale", Le times "Lescale".
void Importer::rgb_grid_medium(const Token& t, const std::string& what, const ParamList& p,
                               Medium& m) {
    int n[3];
    const int count = grid_samples(t, what, p, n);
    const std::vector<RGB> sa = p.colors("sigma_a"), ss = p.colors("sigma_s"), le = p.colors("Le");
    if (sa.empty() && ss.empty())
        fail(t, what + ": an rgbgrid needs \"sigma_a\" and/or \"sigma_s\"");
    if (!le.empty() && sa.empty()) fail(t, what + ": an rgbgrid's \"Le\" needs \"sigma_a\"");
    for (const auto& [key, v] :
         {std::pair{"sigma_a", &sa}, std::pair{"sigma_s", &ss}, std::pair{"Le", &le}})
        if (!v->empty() && v->size() != std::size_t(count))
            fail(t, what + ": \"" + key + "\" has " + std::to_string(v->size()) +
                        " values, nx * ny * nz is " + std::to_string(count));
    const Bounds3 box = grid_box(t, what, p);
    m.kind = MediumKind::RGBGrid;
    m.grid_scale = p.real("scale", 1.f);
    // Each sample's largest channel of extinction bounds the coefficients near it.
    std::vector<float> bound(static_cast<std::size_t>(count));
    for (std::size_t i = 0; i < bound.size(); ++i) {
        const RGB e = (sa.empty() ? RGB{1.f} : sa[i]) + (ss.empty() ? RGB{1.f} : ss[i]);
        bound[i] = e.max_component();
        if (!(bound[i] * m.grid_scale < 1e12f))
            fail(t, what + ": the extinction must be below 1e12");
    }
    auto grid = [&](const std::vector<RGB>& v) {
        return v.empty() ? nullptr : std::make_shared<const RGBGrid>(n[0], n[1], n[2], v, box);
    };
    m.rgb_sigma_a = grid(sa);
    m.rgb_sigma_s = grid(ss);
    m.rgb_Le = grid(le);
    m.le_factor = p.real("Lescale", 1.f) * kCieYIntegral;
    if (!(m.le_factor >= 0.f)) fail(t, what + ": Lescale must not be negative");
    m.density = std::make_shared<const DensityGrid>(n[0], n[1], n[2], std::move(bound), box);
}

// pbrt-v4's nanovdb: the grid "gridname" (default "density") of a NanoVDB file (foton reads
// OpenVDB files too), placed by the transform current at MakeNamedMedium. A grid named
// "temperaturename" (default "temperature") in the file makes the medium glow as a blackbody
// at (temperature - "temperatureoffset") x "temperaturescale" kelvin, times "Lescale"
// (pbrt-v4's; 0 turns it off), where it absorbs.
void Importer::nanovdb_medium(const Token& t, const std::string& what, const ParamList& p,
                              Medium& m) {
    const std::string rel = p.text("filename", "");
    if (rel.empty()) fail(t, what + " needs \"string filename\"");
    const std::string path = input_path(t, "volume file", rel, uint64_t(16) << 30);
    const std::string grid = p.text("gridname", "density");
    const std::string temperature = p.text("temperaturename", "temperature");
    const float le_scale = p.real("Lescale", 1.f);
    if (!(le_scale >= 0.f)) fail(t, what + ": Lescale must not be negative");
    m.temperature_offset = p.real("temperatureoffset", p.real("temperaturecutoff", 0.f));
    m.temperature_scale = p.real("temperaturescale", 1.f);
    m.kind = MediumKind::Grid;
    try {
        std::vector<std::string> names = vdb_grid_names(path);
        m.density = read_vdb_density(path, grid, gs_.ctm);
        if (le_scale > 0.f && std::find(names.begin(), names.end(), temperature) != names.end()) {
            m.temperature = read_vdb_density(path, temperature, gs_.ctm);
            m.le_factor = le_scale;
            const float hottest =
                (m.temperature->max_value() - m.temperature_offset) * m.temperature_scale;
            m.blackbody = std::make_shared<const BlackbodyTable>(blackbody_emission_rgb, hottest);
        }
    } catch (const VdbError& e) {
        fail(t, what + ": volume file '" + rel + "': " + e.what());
    }
}

}  // namespace foton::pbrt
