// <lights>, and the area lights of emissive quads.
#include <filesystem>

#include "loader.h"

namespace foton::xml {

void Loader::parse_lights(const pugi::xml_node& n) {
    check(n, {}, {"point", "directional", "spot", "area", "environment"});
    for (const pugi::xml_node& l : n.children()) {
        if (l.type() != pugi::node_element) continue;
        const std::string_view kind = l.name();
        if (kind == "point") {
            check(l, {"intensity", "attenuation"}, {"color", "position"});
            PointLight p;
            p.position = xyz_child(l, "position");
            p.intensity =
                emitted(l, rgb_child(l, "color", RGB{1.f}) * non_negative(l, "intensity", 1.f));
            p.attenuation = non_negative(l, "attenuation", 0.f);
            scene_.lights.points.push_back(p);
        } else if (kind == "directional") {
            check(l, {"intensity"}, {"color", "direction"});
            DirectionalLight d;
            d.direction = direction(l, "direction");
            d.radiance =
                emitted(l, rgb_child(l, "color", RGB{1.f}) * non_negative(l, "intensity", 1.f));
            scene_.lights.directionals.push_back(d);
        } else if (kind == "spot") {
            check(l, {"intensity", "attenuation", "angle", "inner_angle", "falloff"},
                  {"color", "position", "direction", "target"});
            SpotLight s;
            s.position = xyz_child(l, "position");
            if (l.child("target")) {
                const Vec3 d = xyz_child(l, "target") - s.position;
                if (length_squared(d) == 0.f) fail(l, "spot target equals its position");
                s.direction = normalize(d);
            } else {
                s.direction = direction(l, "direction");
            }
            s.intensity =
                emitted(l, rgb_child(l, "color", RGB{1.f}) * non_negative(l, "intensity", 1.f));
            s.attenuation = non_negative(l, "attenuation", 0.f);
            const float outer = number(l, "angle");
            if (!(outer > 0.f && outer <= 180.f)) fail(l, "spot angle must be in (0, 180] degrees");
            float inner = outer;
            if (l.attribute("inner_angle")) {
                inner = number(l, "inner_angle");
                if (!(inner >= 0.f && inner <= outer)) fail(l, "inner_angle must be in [0, angle]");
            } else if (l.attribute("falloff")) {
                const float f = number(l, "falloff");
                if (!(f >= 0.f && f <= 1.f)) fail(l, "falloff must be in [0, 1]");
                inner = outer * (1.f - f);
            }
            s.cos_outer = std::cos(outer * kPi / 180.f);
            s.cos_inner = std::cos(inner * kPi / 180.f);
            scene_.lights.spots.push_back(s);
        } else if (kind == "environment") {
            add_environment(l);
        } else {
            add_area_light(l);
        }
    }
}

// <environment>: a constant sky (color x intensity), or an image (src) times them, oriented
// by <up> (the map's top; default +y) and <front> (longitude 0; default +z); with <portal>
// (four <corner>s round a rectangle) the light arrives only through it (pbrt-v4's portal
// light; an image must be equal-area). Several <environment>s add up.
void Loader::add_environment(const pugi::xml_node& l) {
    check(l, {"intensity", "src", "mapping", "sampling"}, {"color", "up", "front", "portal"});
    const RGB scale =
        emitted(l, rgb_child(l, "color", RGB{1.f}) * non_negative(l, "intensity", 1.f));
    const std::string src = l.attribute("src").value();
    Vec3 corners[4];
    const pugi::xml_node portal = l.child("portal");
    if (portal) {
        check(portal, {}, {"corner"});
        int k = 0;
        for (const pugi::xml_node c : portal.children("corner")) {
            if (k == 4) fail(portal, "a <portal> has 4 <corner>s");
            corners[k++] = xyz(c);
        }
        if (k != 4) fail(portal, "a <portal> has 4 <corner>s");
        if (!Environment::is_rectangle(corners))
            fail(portal, "a portal must be a rectangle (4 corners in order round it)");
    }
    auto place = [&](Environment e) {
        if (scene_.environment)
            scene_.environment->add(e);
        else
            scene_.environment = std::move(e);
    };
    if (src.empty()) {
        if (l.attribute("mapping") || l.child("up") || l.child("front") || l.attribute("sampling"))
            fail(l,
                 "mapping, sampling, <up> and <front> concern an image: give src or leave them "
                 "out");
        if (!portal) return place(Environment::constant(scale));
        TextureImage one;
        one.width = one.height = 1;
        one.path = name_;
        one.texels = {RGB{1.f}};
        try {
            return place(Environment::portal(one, scale, {0, 1, 0}, {0, 0, 1}, corners));
        } catch (const InputError& e) {
            fail(portal, e.what());
        }
    }
    const std::string mapping = l.attribute("mapping") ? l.attribute("mapping").value() : "latlong";
    EnvMapping m;
    if (mapping == "latlong")
        m = EnvMapping::LatLong;
    else if (mapping == "equalarea")
        m = EnvMapping::EqualArea;
    else
        fail(l, "unknown environment mapping '" + mapping + "' (latlong, equalarea)");
    if (portal && m != EnvMapping::EqualArea)
        fail(portal, "a portal's map is an equal-area one (mapping=\"equalarea\")");
    const Vec3 up = l.child("up") ? direction(l, "up") : Vec3{0, 1, 0};
    const Vec3 front = l.child("front") ? direction(l, "front") : Vec3{0, 0, 1};
    if (length_squared(cross(up, front)) < 1e-8f) fail(l, "<front> is parallel to <up>");
    const std::string path = (std::filesystem::path(base_) / src).string();
    try {
        TextureImage map = load_texture_image(path);
        place(portal ? Environment::portal(map, scale, up, front, corners)
                     : Environment::image(std::move(map), m, scale, up, front));
    } catch (const InputError& e) {
        fail(l, "environment map '" + src + "': " + e.what());
    }
    // The sampling concerns the whole environment (the last <environment> that says).
    if (!l.attribute("sampling")) return;
    const std::string sampling = l.attribute("sampling").value();
    if (sampling != "importance" && sampling != "uniform")
        fail(l, "unknown environment sampling '" + sampling + "' (importance, uniform)");
    scene_.environment->set_uniform_sampling(sampling == "uniform");
}

void Loader::add_area_light(const pugi::xml_node& l) {
    check(l, {"intensity", "samples", "sampler", "visible"},
          {"color", "radiance", "corner", "edge1", "edge2", "center", "size", "normal"});
    AreaLight a;
    if (l.child("corner")) {
        a.corner = xyz_child(l, "corner");
        a.edge1 = xyz_child(l, "edge1");
        a.edge2 = xyz_child(l, "edge2");
    } else if (l.child("center")) {
        const Vec3 c = xyz_child(l, "center");
        const pugi::xml_node sz = child(l, "size");
        check(sz, {"x", "y"}, {});
        const float w = number(sz, "x"), h = number(sz, "y");
        if (!(w > 0.f && h > 0.f)) fail(sz, "area light size must be positive");
        const Vec3 nrm = direction(l, "normal");
        Vec3 s, t;
        orthonormal_basis(nrm, s, t);
        if (dot(cross(s, t), nrm) < 0.f) std::swap(s, t);
        a.edge1 = s * w;
        a.edge2 = t * h;
        a.corner = c - a.edge1 * 0.5f - a.edge2 * 0.5f;
    } else {
        fail(l, "<area> needs <corner> <edge1> <edge2> or <center> <size> <normal>");
    }
    const Vec3 cr = cross(a.edge1, a.edge2);
    a.area = length(cr);
    if (!(a.area > 0.f)) fail(l, "area light has zero area (parallel or zero edges)");
    a.normal = cr / a.area;
    if (l.child("radiance")) {
        check(l.child("radiance"), {"r", "g", "b"}, {});
        a.radiance = emitted(l, rgb(l.child("radiance")) * non_negative(l, "intensity", 1.f));
    } else {
        a.radiance =
            emitted(l, rgb_child(l, "color", RGB{1.f}) * non_negative(l, "intensity", 1.f));
    }
    a.samples = count(l, "samples", 16);
    a.sampler = scene_.renderer.choice("sampler", sampler_names(), SamplerKind::Jittered);
    if (l.attribute("sampler")) {
        const auto k = parse_sampler(l.attribute("sampler").value());
        if (!k) fail(l, std::string("unknown sampler '") + l.attribute("sampler").value() + "'");
        a.sampler = *k;
    }
    if (boolean(l, "visible", true)) {
        // The emitting rectangle itself, so that camera rays and mirrors see the light.
        Material m;
        m.type = MaterialType::Emitter;
        m.name = "area light";
        m.base_color = RGB{0.f};
        m.emission = a.radiance;
        scene_.materials.push_back(m);
        TriangleMesh quad;
        quad.name = "area light";
        const Vec3 p[4] = {a.corner, a.corner + a.edge1, a.corner + a.edge1 + a.edge2,
                           a.corner + a.edge2};
        for (const Vec3& v : p) quad.positions.insert(quad.positions.end(), {v.x, v.y, v.z});
        quad.indices = {0, 1, 2, 0, 2, 3};
        a.geometry = scene_.add_mesh(std::move(quad), uint32_t(scene_.materials.size() - 1), false);
    }
    scene_.lights.areas.push_back(a);
}

}  // namespace foton::xml
