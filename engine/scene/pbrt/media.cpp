// MakeNamedMedium, MediumInterface and the camera's medium: pbrt-v4's participating media as
// foton's (scene/medium.h): homogeneous, uniformgrid, rgbgrid and nanovdb media (their grids:
// media_grids.cpp).
#include "engine/scene/measured_media.h"
#include "importer.h"

namespace foton::pbrt {

void Importer::make_named_medium(const Token& t, const std::string& name, const ParamList& p) {
    const std::string type = p.text("type", "");
    const std::string what = "MakeNamedMedium \"" + name + "\"";
    if (type.empty()) fail(t, what + " needs \"string type\"");
    if (type != "homogeneous" && type != "uniformgrid" && type != "rgbgrid" && type != "nanovdb")
        fail(t, what + ": medium type '" + type +
                    "' is not supported yet (homogeneous, uniformgrid, rgbgrid, nanovdb)");
    if (media_.count(name)) fail(t, what + ": defined twice");
    // A preset (measured_media.h) stands for sigma_a and sigma_s.
    const MeasuredMedium* preset = nullptr;
    if (p.has("preset")) {
        if (type != "homogeneous") fail(t, what + ": only a homogeneous medium takes a preset");
        preset = find_measured_medium(p.text("preset", ""));
        if (!preset)
            fail(t, what + ": unknown preset '" + p.text("preset", "") + "' (" +
                        measured_media_names() + ")");
    }
    Medium m;
    m.name = name;
    const float scale = p.real("scale", 1.f);
    if (!(scale >= 0.f && scale < 1e12f)) fail(t, what + ": scale must be in [0, 1e12)");
    m.g = p.real("g", 0.f);
    if (!(m.g > -1.f && m.g < 1.f)) fail(t, what + ": g must be in (-1, 1)");
    if (type == "rgbgrid") {
        rgb_grid_medium(t, what, p, m);
    } else {
        // pbrt-v4's defaults: sigma_a = sigma_s = 1 per unit length, times scale.
        const auto sa = p.color("sigma_a", false), ss = p.color("sigma_s", false);
        if (preset && (sa || ss))
            fail(t, what + ": give a preset or sigma_a and sigma_s, not both");
        m.sigma_a = (preset ? preset->sigma_a : sa ? *sa : RGB{1.f}) * scale;
        m.sigma_s = (preset ? preset->sigma_s : ss ? *ss : RGB{1.f}) * scale;
        if (!(m.majorant() < 1e12f)) fail(t, what + ": the extinction must be below 1e12");
        const auto le = p.color("Le", true);
        if (le) m.Le = *le;
        if (type == "uniformgrid") {
            m.kind = MediumKind::Grid;
            m.density = uniform_grid(t, what, p);
            if (p.has("temperature")) {
                if (le) fail(t, what + ": give \"Le\" or \"temperature\", not both");
                uniform_temperature(t, what, p, m);
            }
            if (le) m.le_scale = emission_scale_grid(t, what, p, *m.density);
        } else if (type == "nanovdb") {
            if (le) fail(t, what + ": a nanovdb medium takes no \"Le\" (pbrt-v4's neither)");
            nanovdb_medium(t, what, p, m);
        } else {
            m.Le *= p.real("Lescale", 1.f);
        }
        if (!(m.Le.r >= 0.f && m.Le.g >= 0.f && m.Le.b >= 0.f))
            fail(t, what + ": Le must not be negative");
    }
    // The film's imaging ratio is applied to Le with the lights' at the end (run()).
    m.file = file();
    m.line = t.line;
    warn_unused(p, what);
    count("MakeNamedMedium " + type);
    media_[name] = int32_t(scene_.media.size());
    scene_.media.push_back(std::move(m));
    scene_.mark_volumetric(file(), t.line);
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
