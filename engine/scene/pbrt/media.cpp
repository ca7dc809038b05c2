// MakeNamedMedium, MediumInterface and the camera's medium: pbrt-v4's participating media as
// foton's (scene/medium.h): homogeneous, uniformgrid and nanovdb media.
#include <algorithm>

#include "engine/scene/vdb_file.h"
#include "importer.h"

namespace foton::pbrt {

void Importer::make_named_medium(const Token& t, const std::string& name, const ParamList& p) {
    const std::string type = p.text("type", "");
    const std::string what = "MakeNamedMedium \"" + name + "\"";
    if (type.empty()) fail(t, what + " needs \"string type\"");
    if (type != "homogeneous" && type != "uniformgrid" && type != "nanovdb")
        fail(t, what + ": medium type '" + type +
                    "' is not supported yet (homogeneous, uniformgrid, nanovdb)");
    if (media_.count(name)) fail(t, what + ": defined twice");
    if (p.has("preset"))
        fail(t, what + ": named scattering presets are not supported (give sigma_a, sigma_s)");
    Medium m;
    m.name = name;
    // pbrt-v4's defaults: sigma_a = sigma_s = 1 per unit length, times scale.
    const float scale = p.real("scale", 1.f);
    if (!(scale >= 0.f)) fail(t, what + ": scale must not be negative");
    const auto sa = p.color("sigma_a", false), ss = p.color("sigma_s", false);
    m.sigma_a = (sa ? *sa : RGB{1.f}) * scale;
    m.sigma_s = (ss ? *ss : RGB{1.f}) * scale;
    if (m.sigma_a.r < 0.f || m.sigma_a.g < 0.f || m.sigma_a.b < 0.f || m.sigma_s.r < 0.f ||
        m.sigma_s.g < 0.f || m.sigma_s.b < 0.f)
        fail(t, what + ": sigma_a and sigma_s must not be negative");
    if (!(m.majorant() < 1e12f)) fail(t, what + ": the extinction must be below 1e12");
    m.g = p.real("g", 0.f);
    if (!(m.g > -1.f && m.g < 1.f)) fail(t, what + ": g must be in (-1, 1)");
    if (type == "uniformgrid") {
        m.kind = MediumKind::Grid;
        m.density = uniform_grid(t, what, p);
        for (const char* emission : {"Le", "Lescale", "temperature", "temperaturescale"})
            if (p.has(emission)) fail(t, what + ": emitting grid media are not supported yet");
    } else if (type == "nanovdb") {
        if (p.has("Le")) fail(t, what + ": a nanovdb medium takes no \"Le\" (pbrt-v4's neither)");
        m.kind = MediumKind::Grid;
        m.density = nanovdb_grid(t, what, p);
    }
    if (const auto le = p.color("Le", true)) {
        // The film's imaging ratio is applied with the lights' at the end (run()).
        m.Le = *le * p.real("Lescale", 1.f);
        if (!(m.Le.r >= 0.f && m.Le.g >= 0.f && m.Le.b >= 0.f))
            fail(t, what + ": Le must not be negative");
    }
    m.file = file();
    m.line = t.line;
    warn_unused(p, what);
    count("MakeNamedMedium " + type);
    media_[name] = int32_t(scene_.media.size());
    scene_.media.push_back(std::move(m));
    scene_.mark_volumetric(file(), t.line);
}

// pbrt-v4's uniformgrid: "density" nx x ny x nz values (x fastest) over the box p0-p1 in the
// medium's space, placed by the transform current at MakeNamedMedium (scales and translations
// only: foton's grids are axis-aligned in the world).
std::shared_ptr<const DensityGrid> Importer::uniform_grid(const Token& t, const std::string& what,
                                                          const ParamList& p) {
    const int nx = p.integer("nx", 1), ny = p.integer("ny", 1), nz = p.integer("nz", 1);
    if (nx < 1 || ny < 1 || nz < 1) fail(t, what + ": nx, ny and nz must be positive");
    std::vector<float> density = p.reals("density");
    if (uint64_t(density.size()) != uint64_t(nx) * uint64_t(ny) * uint64_t(nz))
        fail(t, what + ": \"density\" has " + std::to_string(density.size()) +
                    " values, nx * ny * nz is " +
                    std::to_string(uint64_t(nx) * uint64_t(ny) * uint64_t(nz)));
    for (float v : density)
        if (!(v >= 0.f)) fail(t, what + ": density values must not be negative");
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
    return std::make_shared<const DensityGrid>(nx, ny, nz, std::move(density), box);
}

// pbrt-v4's nanovdb: the grid "gridname" (default "density") of a NanoVDB file (foton reads
// OpenVDB files too), placed by the transform current at MakeNamedMedium. pbrt-v4 makes a
// "temperature" grid in the file glow as a blackbody; foton does not, so such a file is refused
// unless "Lescale" is 0.
std::shared_ptr<const DensityGrid> Importer::nanovdb_grid(const Token& t, const std::string& what,
                                                          const ParamList& p) {
    const std::string rel = p.text("filename", "");
    if (rel.empty()) fail(t, what + " needs \"string filename\"");
    const std::string path = input_path(t, "volume file", rel, uint64_t(16) << 30);
    const std::string grid = p.text("gridname", "density");
    const std::string temperature = p.text("temperaturename", "temperature");
    const float le_scale = p.real("Lescale", 1.f);
    for (const char* unused : {"temperatureoffset", "temperaturecutoff", "temperaturescale"})
        if (p.has(unused)) p.real(unused, 0.f);
    try {
        std::vector<std::string> names = vdb_grid_names(path);
        const bool has_temperature =
            std::find(names.begin(), names.end(), temperature) != names.end();
        if (has_temperature && le_scale != 0.f)
            fail(t, what + ": '" + rel + "' has a \"" + temperature +
                        "\" grid, whose blackbody emission foton does not render (give "
                        "\"float Lescale\" 0 to render the medium without it)");
        return read_vdb_density(path, grid, gs_.ctm);
    } catch (const VdbError& e) {
        fail(t, what + ": volume file '" + rel + "': " + e.what());
    }
}

void Importer::medium_interface(const Token& t) {
    const std::string inside(expect_string(t, "the inside medium's name").text);
    std::string outside = inside;
    // One name is both sides; a second string is the outside.
    if (files_.back()->peek().kind == TokenKind::String) outside = std::string(next().text);
    gs_.medium_inside = inside;
    gs_.medium_outside = outside;
    gs_.medium_file = file();
    gs_.medium_line = t.line;
}

int32_t Importer::medium_id(const std::string& name, const std::string& where, int line) const {
    if (name.empty()) return kNoMedium;
    const auto it = media_.find(name);
    if (it == media_.end())
        throw InputError(where, line,
                         "unknown medium '" + name + "' (define it with MakeNamedMedium first)");
    return it->second;
}

MediumInterface Importer::shape_media() const {
    MediumInterface mi;
    mi.inside = medium_id(gs_.medium_inside, gs_.medium_file, gs_.medium_line);
    mi.outside = medium_id(gs_.medium_outside, gs_.medium_file, gs_.medium_line);
    return mi;
}

}  // namespace foton::pbrt
