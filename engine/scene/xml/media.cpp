// <media>: participating media by name, and the medium references of the camera and objects.
#include <cstring>
#include <filesystem>

#include "engine/core/input_file.h"
#include "engine/scene/vdb_file.h"
#include "loader.h"

namespace foton::xml {

void Loader::parse_media(const pugi::xml_node& n) {
    check(n, {}, {"medium"});
    for (const pugi::xml_node& e : n.children("medium")) {
        check(e, {"name", "type", "g", "scale", "nx", "ny", "nz", "src", "grid"},
              {"sigma_a", "sigma_s", "emission", "p0", "p1", "transform"});
        Medium m;
        m.name = e.attribute("name").value();
        if (m.name.empty()) fail(e, "<medium> needs attribute 'name'");
        if (medium_ids_.count(m.name)) fail(e, "medium '" + m.name + "' defined twice");
        const std::string type = e.attribute("type") ? e.attribute("type").value() : "homogeneous";
        if (type != "homogeneous" && type != "grid" && type != "vdb")
            fail(e, "unknown medium type '" + type + "' (homogeneous, grid, vdb)");
        if (type != "vdb") {
            if (e.attribute("grid")) fail(e, "'grid' belongs to a vdb medium");
            if (e.child("transform")) fail(e, "<transform> belongs to a vdb medium");
        }
        if (type == "grid") {
            m.kind = MediumKind::Grid;
            m.density = density_grid(e);
        } else if (type == "vdb") {
            m.kind = MediumKind::Grid;
            m.density = vdb_grid(e);
        } else {
            for (const char* a : {"nx", "ny", "nz", "src"})
                if (e.attribute(a)) fail(e, std::string("'") + a + "' belongs to a grid medium");
            if (e.child("p0") || e.child("p1")) fail(e, "<p0>, <p1> belong to a grid medium");
        }
        // Coefficients per unit of scene length; `scale` multiplies both (pbrt-v4's scale).
        const float scale = non_negative(e, "scale", 1.f);
        m.sigma_a = rgb_child(e, "sigma_a", RGB{0.f}) * scale;
        m.sigma_s = rgb_child(e, "sigma_s", RGB{0.f}) * scale;
        m.g = number(e, "g", 0.f);
        if (!(m.g > -1.f && m.g < 1.f)) fail(e, "the phase function's g must be in (-1, 1)");
        if (!e.child("sigma_a") && !e.child("sigma_s"))
            fail(e, "<medium> needs <sigma_a> or <sigma_s> (per unit length)");
        if (!(m.majorant() < 1e12f))
            fail(e, "the medium's extinction must be below 1e12 per unit length");
        if (const pugi::xml_node le = e.child("emission")) {
            check(le, {"r", "g", "b", "intensity"}, {});
            m.Le = emitted(le, rgb(le, {"intensity"}) * non_negative(le, "intensity", 1.f));
            if (m.sigma_a.is_black())
                fail(le, "an emitting medium needs absorption (it emits sigma_a Le)");
            if (m.kind == MediumKind::Grid) fail(le, "grid media do not emit (yet)");
        }
        m.file = name_;
        m.line = line_of(e);
        medium_ids_[m.name] = int32_t(scene_.media.size());
        scene_.media.push_back(std::move(m));
        scene_.mark_volumetric(name_, line_of(e));
    }
}

// A grid medium's density: nx x ny x nz little-endian float32 values, x fastest, from the
// file `src`, over the box from <p0> to <p1>.
std::shared_ptr<const DensityGrid> Loader::density_grid(const pugi::xml_node& e) const {
    const uint32_t n[3] = {count(e, "nx", 0), count(e, "ny", 0), count(e, "nz", 0)};
    if (!n[0] || !n[1] || !n[2]) fail(e, "a grid medium needs nx, ny and nz");
    if (uint64_t(n[0]) * n[1] * n[2] > (uint64_t(1) << 28))
        fail(e, "a grid medium has at most 2^28 samples");
    const std::string src = e.attribute("src").value();
    if (src.empty()) fail(e, "a grid medium needs 'src' (raw little-endian float32 samples)");
    const std::string path = (std::filesystem::path(base_) / src).string();
    const std::string problem = input_file_problem(path, uint64_t(4) << 30);
    if (!problem.empty()) fail(e, "density file '" + src + "': " + problem);
    const std::string bytes = read_input_file(path, uint64_t(4) << 30, "density file");
    const std::size_t count_values = std::size_t(n[0]) * n[1] * n[2];
    if (bytes.size() != 4 * count_values)
        fail(e, "density file '" + src + "' has " + std::to_string(bytes.size()) +
                    " bytes; nx * ny * nz float32 samples are " + std::to_string(4 * count_values));
    std::vector<float> values(count_values);
    std::memcpy(values.data(), bytes.data(), bytes.size());
    for (std::size_t i = 0; i < values.size(); ++i)
        if (!(values[i] >= 0.f && values[i] < 1e12f))
            fail(e, "density file '" + src + "': sample " + std::to_string(i) +
                        " is negative, not finite or beyond 1e12");
    Bounds3 box;
    box.extend(xyz_child(e, "p0"));
    box.extend(xyz_child(e, "p1"));
    const Vec3 ext = box.diagonal();
    if (!(ext.x > 0.f && ext.y > 0.f && ext.z > 0.f)) fail(e, "the grid's box <p0>-<p1> is empty");
    return std::make_shared<const DensityGrid>(int(n[0]), int(n[1]), int(n[2]), std::move(values),
                                               box);
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

int32_t Loader::medium_ref(const pugi::xml_node& n, const char* attr) const {
    const pugi::xml_attribute a = n.attribute(attr);
    if (!a || !*a.value()) return kNoMedium;  // "" is vacuum, as in pbrt-v4
    const auto it = medium_ids_.find(a.value());
    if (it == medium_ids_.end()) {
        std::string names;
        for (const auto& [name, id] : medium_ids_) names += (names.empty() ? "" : ", ") + name;
        fail(n, std::string("unknown medium '") + a.value() + "' in attribute '" + attr + "' (" +
                    (names.empty() ? "no <media> defined" : names) + ")");
    }
    return it->second;
}

MediumInterface Loader::medium_interface(const pugi::xml_node& object) const {
    MediumInterface mi;
    mi.inside = medium_ref(object, "medium_inside");
    mi.outside = medium_ref(object, "medium_outside");
    return mi;
}

}  // namespace foton::xml
