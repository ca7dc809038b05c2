// The grids of <medium type="grid|rgbgrid|vdb">: raw float32 sample files and VDB files.
#include <cstring>
#include <filesystem>

#include "engine/core/input_file.h"
#include "engine/scene/pbrt/spectrum.h"
#include "engine/scene/vdb_file.h"
#include "loader.h"

namespace foton::xml {

// The little-endian float32 values of the file named by attribute `attr`, exactly `count` of
// them, each finite, non-negative and below 1e12.
std::vector<float> Loader::raw_floats(const pugi::xml_node& e, const char* attr,
                                      std::size_t count) const {
    const std::string src = e.attribute(attr).value();
    if (src.empty()) fail(e, std::string("'") + attr + "' names no file");
    const std::string path = (std::filesystem::path(base_) / src).string();
    const std::string problem = input_file_problem(path, uint64_t(4) << 30);
    if (!problem.empty()) fail(e, "sample file '" + src + "': " + problem);
    const std::string bytes = read_input_file(path, uint64_t(4) << 30, "sample file");
    if (bytes.size() != 4 * count)
        fail(e, "sample file '" + src + "' has " + std::to_string(bytes.size()) + " bytes; " +
                    std::to_string(count) + " float32 values are " + std::to_string(4 * count));
    std::vector<float> values(count);
    std::memcpy(values.data(), bytes.data(), bytes.size());
    for (std::size_t i = 0; i < values.size(); ++i)
        if (!(values[i] >= 0.f && values[i] < 1e12f))
            fail(e, "sample file '" + src + "': value " + std::to_string(i) +
                        " is negative, not finite or beyond 1e12");
    return values;
}

// nx, ny, nz (each at least 1, at most 2^28 samples in all).
std::size_t Loader::grid_counts(const pugi::xml_node& e, int n[3]) const {
    const uint32_t c[3] = {count(e, "nx", 0), count(e, "ny", 0), count(e, "nz", 0)};
    if (!c[0] || !c[1] || !c[2]) fail(e, "a grid medium needs nx, ny and nz");
    if (uint64_t(c[0]) * c[1] * c[2] > (uint64_t(1) << 28))
        fail(e, "a grid medium has at most 2^28 samples");
    for (int a = 0; a < 3; ++a) n[a] = int(c[a]);
    return std::size_t(c[0]) * c[1] * c[2];
}

Bounds3 Loader::grid_box(const pugi::xml_node& e) const {
    Bounds3 box;
    box.extend(xyz_child(e, "p0"));
    box.extend(xyz_child(e, "p1"));
    const Vec3 ext = box.diagonal();
    if (!(ext.x > 0.f && ext.y > 0.f && ext.z > 0.f)) fail(e, "the grid's box <p0>-<p1> is empty");
    return box;
}

// A grid medium's density: nx x ny x nz little-endian float32 values, x fastest, from the
// file `src`, over the box from <p0> to <p1>.
std::shared_ptr<const DensityGrid> Loader::density_grid(const pugi::xml_node& e) const {
    int n[3];
    const std::size_t count = grid_counts(e, n);
    if (!e.attribute("src"))
        fail(e, "a grid medium needs 'src' (raw little-endian float32 samples)");
    std::vector<float> values = raw_floats(e, "src", count);
    return std::make_shared<const DensityGrid>(n[0], n[1], n[2], std::move(values), grid_box(e));
}

// An rgbgrid medium: sigma_a, sigma_s and emitted radiance as RGB grids (nx x ny x nz float32
// triples each, x fastest) from `sigma_a_src`, `sigma_s_src`, `emission_src` (a coefficient
// left out is 0; no emission without absorption); `scale` multiplies the coefficients,
// `emission_scale` the emission.
void Loader::rgb_grid_medium(const pugi::xml_node& e, float scale, Medium& m) const {
    int n[3];
    const std::size_t count = grid_counts(e, n);
    const bool has_a = bool(e.attribute("sigma_a_src")), has_s = bool(e.attribute("sigma_s_src"));
    if (!has_a && !has_s) fail(e, "an rgbgrid medium needs 'sigma_a_src' or 'sigma_s_src'");
    if (e.attribute("emission_src") && !has_a)
        fail(e, "an emitting medium needs absorption (it emits sigma_a Le): give 'sigma_a_src'");
    auto triples = [&](const char* attr) {
        std::vector<RGB> v(count, RGB{0.f});
        if (!e.attribute(attr)) return v;
        const std::vector<float> f = raw_floats(e, attr, 3 * count);
        for (std::size_t i = 0; i < count; ++i) v[i] = {f[3 * i], f[3 * i + 1], f[3 * i + 2]};
        return v;
    };
    const std::vector<RGB> sa = triples("sigma_a_src"), ss = triples("sigma_s_src");
    const Bounds3 box = grid_box(e);
    std::vector<float> bound(count);
    for (std::size_t i = 0; i < count; ++i) {
        bound[i] = (sa[i] + ss[i]).max_component();
        if (!(bound[i] * scale < 1e12f))
            fail(e, "the medium's extinction must be below 1e12 per unit length");
    }
    m.kind = MediumKind::RGBGrid;
    m.grid_scale = scale;
    m.rgb_sigma_a = std::make_shared<const RGBGrid>(n[0], n[1], n[2], sa, box);
    m.rgb_sigma_s = std::make_shared<const RGBGrid>(n[0], n[1], n[2], ss, box);
    if (e.attribute("emission_src")) {
        m.rgb_Le = std::make_shared<const RGBGrid>(n[0], n[1], n[2], triples("emission_src"), box);
        m.le_factor = non_negative(e, "emission_scale", 1.f);
    }
    m.density = std::make_shared<const DensityGrid>(n[0], n[1], n[2], std::move(bound), box);
}

// A vdb medium's density: the float grid `grid` (default "density") of the OpenVDB or NanoVDB
// file `src`, placed by its own transform and then the medium's <transform>.
std::shared_ptr<const DensityGrid> Loader::vdb_grid(const pugi::xml_node& e) const {
    for (const char* a : {"nx", "ny", "nz"})
        if (e.attribute(a)) fail(e, std::string("'") + a + "' belongs to a grid medium");
    if (e.child("p0") || e.child("p1")) fail(e, "<p0>, <p1> belong to a grid medium");
    const std::string src = e.attribute("src").value();
    if (src.empty()) fail(e, "a vdb medium needs 'src' (an OpenVDB .vdb or NanoVDB .nvdb file)");
    const std::string grid = e.attribute("grid") ? e.attribute("grid").value() : "density";
    const std::string path = (std::filesystem::path(base_) / src).string();
    const std::string problem = input_file_problem(path, uint64_t(16) << 30);
    if (!problem.empty()) fail(e, "volume file '" + src + "': " + problem);
    try {
        return read_vdb_density(path, grid, parse_transform(e));
    } catch (const VdbError& err) {
        std::string names;
        try {
            for (const std::string& n : vdb_grid_names(path))
                names += (names.empty() ? "" : ", ") + n;
        } catch (const VdbError&) {
        }
        fail(e, "volume file '" + src + "': " + err.what() +
                    (names.empty() ? "" : " (its grids: " + names + ")"));
    }
}

// A vdb medium's glow: the file's grid `temperature` read as the density is, glowing as pbrt-v4's
// peak-normalised blackbody at (T - temperature_offset) x temperature_scale kelvin (nothing
// below 100 K), times emission_scale.
void Loader::vdb_temperature(const pugi::xml_node& e, Medium& m) const {
    const std::string src = e.attribute("src").value();
    const std::string path = (std::filesystem::path(base_) / src).string();
    try {
        m.temperature =
            read_vdb_density(path, e.attribute("temperature").value(), parse_transform(e));
    } catch (const VdbError& err) {
        fail(e, "volume file '" + src + "': " + err.what());
    }
    m.temperature_offset = number(e, "temperature_offset", 0.f);
    m.temperature_scale = non_negative(e, "temperature_scale", 1.f);
    m.le_factor = non_negative(e, "emission_scale", 1.f);
    const float hottest = (m.temperature->max_value() - m.temperature_offset) * m.temperature_scale;
    m.blackbody = std::make_shared<const BlackbodyTable>(pbrt::blackbody_emission_rgb, hottest);
}

}  // namespace foton::xml
