// <media>: participating media by name, and the medium references of the camera and objects.
#include "engine/core/input_file.h"
#include "loader.h"

namespace foton::xml {

void Loader::parse_media(const pugi::xml_node& n) {
    check(n, {}, {"medium"});
    for (const pugi::xml_node& e : n.children("medium")) {
        check(e,
              {"name", "type", "g", "scale", "nx", "ny", "nz", "src", "grid", "sigma_a_src",
               "sigma_s_src", "emission_src", "emission_scale", "temperature", "temperature_offset",
               "temperature_scale"},
              {"sigma_a", "sigma_s", "emission", "p0", "p1", "transform"});
        Medium m;
        m.name = e.attribute("name").value();
        if (m.name.empty()) fail(e, "<medium> needs attribute 'name'");
        if (medium_ids_.count(m.name)) fail(e, "medium '" + m.name + "' defined twice");
        const std::string type = e.attribute("type") ? e.attribute("type").value() : "homogeneous";
        if (type != "homogeneous" && type != "grid" && type != "vdb" && type != "rgbgrid")
            fail(e, "unknown medium type '" + type + "' (homogeneous, grid, rgbgrid, vdb)");
        const bool grid = type == "grid", vdb = type == "vdb", rgbgrid = type == "rgbgrid";
        // What belongs to some types only.
        auto only = [&](const char* name, bool child, bool allowed, const char* owner) {
            const bool present = child ? bool(e.child(name)) : bool(e.attribute(name));
            if (present && !allowed)
                fail(e, (child ? std::string("<") + name + ">" : std::string("'") + name + "'") +
                            " belongs to " + owner);
        };
        for (const char* a : {"nx", "ny", "nz"}) only(a, false, grid || rgbgrid, "a grid medium");
        only("p0", true, grid || rgbgrid, "a grid medium");
        only("p1", true, grid || rgbgrid, "a grid medium");
        only("src", false, grid || vdb, "a grid or vdb medium");
        only("grid", false, vdb, "a vdb medium");
        only("transform", true, vdb, "a vdb medium");
        for (const char* a : {"sigma_a_src", "sigma_s_src", "emission_src"})
            only(a, false, rgbgrid, "an rgbgrid medium");
        only("emission_scale", false, rgbgrid || vdb, "an rgbgrid or vdb medium");
        for (const char* a : {"temperature", "temperature_offset", "temperature_scale"})
            only(a, false, vdb, "a vdb medium");
        for (const char* c : {"sigma_a", "sigma_s", "emission"})
            only(c, true, !rgbgrid, "media other than rgbgrid");
        m.g = number(e, "g", 0.f);
        if (!(m.g > -1.f && m.g < 1.f)) fail(e, "the phase function's g must be in (-1, 1)");
        // Coefficients per unit of scene length; `scale` multiplies both (pbrt-v4's scale).
        const float scale = non_negative(e, "scale", 1.f);
        if (rgbgrid) {
            rgb_grid_medium(e, scale, m);
        } else {
            if (grid) {
                m.kind = MediumKind::Grid;
                m.density = density_grid(e);
            } else if (vdb) {
                m.kind = MediumKind::Grid;
                m.density = vdb_grid(e);
                if (e.attribute("temperature")) vdb_temperature(e, m);
            }
            m.sigma_a = rgb_child(e, "sigma_a", RGB{0.f}) * scale;
            m.sigma_s = rgb_child(e, "sigma_s", RGB{0.f}) * scale;
            if (!e.child("sigma_a") && !e.child("sigma_s"))
                fail(e, "<medium> needs <sigma_a> or <sigma_s> (per unit length)");
            if (!(m.majorant() < 1e12f))
                fail(e, "the medium's extinction must be below 1e12 per unit length");
            if (m.temperature && m.sigma_a.is_black())
                fail(e, "a glowing medium needs absorption (it emits sigma_a Le): give <sigma_a>");
            if (const pugi::xml_node le = e.child("emission")) {
                if (m.temperature)
                    fail(le, "a medium glows by its temperature or <emission>, not both");
                check(le, {"r", "g", "b", "intensity"}, {});
                m.Le = emitted(le, rgb(le, {"intensity"}) * non_negative(le, "intensity", 1.f));
                if (m.sigma_a.is_black())
                    fail(le, "an emitting medium needs absorption (it emits sigma_a Le)");
            }
        }
        m.file = name_;
        m.line = line_of(e);
        medium_ids_[m.name] = int32_t(scene_.media.size());
        scene_.media.push_back(std::move(m));
        scene_.mark_volumetric(name_, line_of(e));
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
