#include "xml_loader.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <vector>

#include <pugixml.hpp>

#include "engine/core/error.h"
#include "obj_loader.h"

namespace foton {

namespace {

using Names = std::initializer_list<const char*>;

bool in(const Names& names, const char* s) {
    return std::any_of(names.begin(), names.end(),
                       [&](const char* n) { return std::string_view(n) == s; });
}

class Loader {
  public:
    Loader(const std::string& xml, std::string name, std::string base_dir,
           const RendererOverrides& overrides)
        : xml_(xml), name_(std::move(name)), base_(std::move(base_dir)), overrides_(overrides) {
        line_starts_.push_back(0);
        for (std::size_t i = 0; i < xml_.size(); ++i)
            if (xml_[i] == '\n') line_starts_.push_back(i + 1);
    }

    Scene run();

  private:
    int line_of(std::ptrdiff_t offset) const {
        if (offset < 0) return 0;
        auto it = std::upper_bound(line_starts_.begin(), line_starts_.end(), std::size_t(offset));
        return int(it - line_starts_.begin());
    }
    int line_of(const pugi::xml_node& n) const { return line_of(n.offset_debug()); }
    [[noreturn]] void fail(const pugi::xml_node& n, const std::string& what) const {
        throw InputError(name_, line_of(n), what);
    }

    // Rejects attributes and child elements that the element does not define.
    void check(const pugi::xml_node& n, const Names& attrs, const Names& children,
               bool any_attribute = false) const {
        for (const pugi::xml_attribute& a : n.attributes())
            if (!any_attribute && !in(attrs, a.name()))
                fail(n, std::string("unknown attribute '") + a.name() + "' on <" + n.name() + ">");
        for (const pugi::xml_node& c : n.children()) {
            if (c.type() != pugi::node_element) continue;
            if (!in(children, c.name()))
                fail(c, std::string("unknown element <") + c.name() + "> in <" + n.name() + ">");
        }
    }

    float number(const pugi::xml_node& n, const char* attr) const {
        const pugi::xml_attribute a = n.attribute(attr);
        if (!a) fail(n, std::string("<") + n.name() + "> needs attribute '" + attr + "'");
        std::string_view s = a.value();
        while (!s.empty() && std::isspace((unsigned char)s.front())) s.remove_prefix(1);
        while (!s.empty() && std::isspace((unsigned char)s.back())) s.remove_suffix(1);
        if (!s.empty() && s.front() == '+') s.remove_prefix(1);
        float v = 0.f;
        auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        if (s.empty() || ec != std::errc() || ptr != s.data() + s.size())
            fail(n, std::string("attribute '") + attr + "' is not a number: '" + a.value() + "'");
        if (!std::isfinite(v)) fail(n, std::string("attribute '") + attr + "' is NaN or infinite");
        return v;
    }
    float number(const pugi::xml_node& n, const char* attr, float fallback) const {
        return n.attribute(attr) ? number(n, attr) : fallback;
    }
    float positive(const pugi::xml_node& n, const char* attr, float fallback) const {
        const float v = number(n, attr, fallback);
        if (!(v > 0.f)) fail(n, std::string("attribute '") + attr + "' must be positive");
        return v;
    }
    float non_negative(const pugi::xml_node& n, const char* attr, float fallback) const {
        const float v = number(n, attr, fallback);
        if (v < 0.f) fail(n, std::string("attribute '") + attr + "' must not be negative");
        return v;
    }
    uint32_t count(const pugi::xml_node& n, const char* attr, uint32_t fallback) const {
        if (!n.attribute(attr)) return fallback;
        const float v = number(n, attr);
        if (v < 1.f || v != std::floor(v) || v > 1e8f)
            fail(n, std::string("attribute '") + attr + "' must be a positive integer");
        return uint32_t(v);
    }
    bool boolean(const pugi::xml_node& n, const char* attr, bool fallback) const {
        const pugi::xml_attribute a = n.attribute(attr);
        if (!a) return fallback;
        const std::string v = a.value();
        if (v == "true" || v == "1") return true;
        if (v == "false" || v == "0") return false;
        fail(n, std::string("attribute '") + attr + "' must be true or false");
    }
    pugi::xml_node child(const pugi::xml_node& n, const char* name) const {
        const pugi::xml_node c = n.child(name);
        if (!c) fail(n, std::string("<") + n.name() + "> needs a <" + name + "> element");
        return c;
    }
    Vec3 xyz(const pugi::xml_node& n) const {
        check(n, {"x", "y", "z"}, {});
        return {number(n, "x"), number(n, "y"), number(n, "z")};
    }
    Vec3 xyz_child(const pugi::xml_node& n, const char* name) const { return xyz(child(n, name)); }
    RGB rgb(const pugi::xml_node& n, Names extra = {}) const {
        for (const pugi::xml_attribute& a : n.attributes()) {
            const std::string_view an = a.name();
            if (an != "r" && an != "g" && an != "b" && !in(extra, a.name()))
                fail(n, std::string("unknown attribute '") + a.name() + "' on <" + n.name() + ">");
        }
        const RGB c{number(n, "r"), number(n, "g"), number(n, "b")};
        if (c.r < 0.f || c.g < 0.f || c.b < 0.f) fail(n, "colour components must not be negative");
        return c;
    }
    RGB rgb_child(const pugi::xml_node& n, const char* name, RGB fallback) const {
        const pugi::xml_node c = n.child(name);
        if (!c) return fallback;
        check(c, {"r", "g", "b"}, {});
        return rgb(c);
    }
    Vec3 direction(const pugi::xml_node& n, const char* name) const {
        const pugi::xml_node c = child(n, name);
        const Vec3 d = xyz(c);
        if (length_squared(d) == 0.f) fail(c, std::string("<") + name + "> is a zero vector");
        return normalize(d);
    }

    void parse_lights(const pugi::xml_node& n);
    void parse_objects(const pugi::xml_node& n);
    void parse_film(const pugi::xml_node& n);
    void parse_renderer(const pugi::xml_node& n);
    void parse_camera(const pugi::xml_node& n);
    uint32_t parse_material(const pugi::xml_node& object);
    Material material(const pugi::xml_node& n, bool top);
    Fresnel conductor_fresnel(const pugi::xml_node& n) const;
    MicrofacetDistribution distribution(const pugi::xml_node& n, const char* fallback) const;
    Affine parse_transform(const pugi::xml_node& object) const;
    void add_area_light(const pugi::xml_node& n);
    uint32_t add_mesh(TriangleMesh mesh, uint32_t material, bool smooth);

    const std::string& xml_;
    std::string name_, base_;
    std::vector<std::size_t> line_starts_;
    const RendererOverrides& overrides_;
    Scene scene_;
};

Scene Loader::run() {
    pugi::xml_document doc;
    const pugi::xml_parse_result r = doc.load_buffer(xml_.data(), xml_.size());
    if (!r)
        throw InputError(name_, line_of(r.offset),
                         std::string("malformed XML: ") + r.description());
    const pugi::xml_node root = doc.document_element();
    if (std::string_view(root.name()) != "scene")
        fail(root, std::string("root element must be <scene>, not <") + root.name() + ">");
    check(
        root, {},
        {"background", "ambient", "lights", "aggregate", "objects", "film", "renderer", "camera"});
    scene_.source = name_;
    for (const char* once : {"background", "ambient", "lights", "aggregate", "objects", "film",
                             "renderer", "camera"}) {
        int k = 0;
        for (const pugi::xml_node& c : root.children(once)) {
            if (++k > 1) fail(c, std::string("<") + once + "> given more than once");
        }
    }
    if (const auto n = root.child("background")) {
        check(n, {"r", "g", "b"}, {});
        scene_.background = rgb(n);
    }
    if (const auto n = root.child("ambient")) {
        check(n, {"r", "g", "b", "intensity"}, {});
        scene_.ambient.color = rgb(n, {"intensity"});
        scene_.ambient.intensity = non_negative(n, "intensity", 1.f);
    }
    // Film before camera: the camera's view plane is film size x pixel count.
    parse_film(child(root, "film"));
    parse_renderer(root.child("renderer"));
    if (const auto n = root.child("aggregate")) {
        check(n, {"type", "density"}, {});
        if (!parse_accel(n.attribute("type").value(), scene_.accel))
            fail(n, std::string("unknown aggregate type '") + n.attribute("type").value() +
                        "' (brute, brute-simd, grid, bvh, embree)");
        scene_.grid_density = positive(n, "density", scene_.grid_density);
    }
    parse_camera(child(root, "camera"));
    if (const auto n = root.child("lights")) parse_lights(n);
    parse_objects(child(root, "objects"));
    bool has_geometry = false;
    for (const Object& o : scene_.objects)
        if (scene_.materials[o.material].type != MaterialType::Emitter) has_geometry = true;
    if (!has_geometry) fail(root.child("objects"), "the scene has no objects");
    return std::move(scene_);
}

void Loader::parse_film(const pugi::xml_node& n) {
    check(n, {"width", "height", "size", "gamma"}, {});
    FilmSettings& f = scene_.film;
    f.width = int(count(n, "width", 512));
    f.height = int(count(n, "height", 512));
    f.pixel_size = positive(n, "size", 0.001f);
    f.gamma = positive(n, "gamma", 2.2f);
}

// The <renderer> attributes, and those of its <adaptive> element as adaptive_*, become
// settings with their line; --set overrides come after them.
void Loader::parse_renderer(const pugi::xml_node& n) {
    ParamSet params;
    params.file = name_;
    if (n) {
        check(n, {}, {"adaptive"}, /*any_attribute=*/true);
        for (const pugi::xml_attribute& a : n.attributes())
            params.set(a.name(), a.value(), name_, line_of(n));
        if (const pugi::xml_node a = n.child("adaptive")) {
            check(a, {"pilot", "max_spp", "threshold", "unbiased", "enabled"}, {});
            params.set("adaptive", a.attribute("enabled") ? a.attribute("enabled").value() : "true",
                       name_, line_of(a));
            for (const pugi::xml_attribute& at : a.attributes())
                if (std::string_view(at.name()) != "enabled")
                    params.set(std::string("adaptive_") + at.name(), at.value(), name_, line_of(a));
        }
    }
    for (const auto& [key, value] : overrides_) params.set(key, value, "--set", 0);
    scene_.render = parse_render_settings(params);
}

void Loader::parse_camera(const pugi::xml_node& n) {
    check(n, {"type", "d", "exposure", "fov", "lens_radius", "focal_distance"},
          {"eye", "target", "up"});
    Camera& c = scene_.camera;
    const std::string type = n.attribute("type") ? n.attribute("type").value() : "perspective";
    if (type == "perspective")
        c.type = CameraType::Perspective;
    else if (type == "orthographic")
        c.type = CameraType::Orthographic;
    else
        fail(n, "unknown camera type '" + type + "' (perspective, orthographic)");
    c.eye = xyz_child(n, "eye");
    c.target = xyz_child(n, "target");
    c.up = n.child("up") ? xyz_child(n, "up") : Vec3{0, 1, 0};
    c.d = positive(n, "d", 1.f);
    c.exposure = positive(n, "exposure", 1.f);
    c.width = scene_.film.width;
    c.height = scene_.film.height;
    if (n.attribute("fov")) {
        // Convenience: a vertical field of view in degrees sets the pixel size.
        const float fov = number(n, "fov");
        if (!(fov > 0.f && fov < 180.f)) fail(n, "fov must be in (0, 180) degrees");
        if (c.type != CameraType::Perspective) fail(n, "fov applies to perspective cameras only");
        scene_.film.pixel_size = 2.f * c.d * std::tan(0.5f * fov * kPi / 180.f) / float(c.height);
    }
    c.pixel_size = scene_.film.pixel_size;
    if (length_squared(c.target - c.eye) == 0.f) fail(n, "camera eye and target coincide");
    c.lens_radius = non_negative(n, "lens_radius", 0.f);
    c.focal_distance = positive(n, "focal_distance", length(c.target - c.eye));
    if (c.lens_radius > 0.f && c.type != CameraType::Perspective)
        fail(n, "a thin lens (lens_radius) needs a perspective camera");
    if (length_squared(cross(c.target - c.eye, c.up)) == 0.f)
        fail(n, "camera up is parallel to the viewing direction");
    c.setup();
}

void Loader::parse_lights(const pugi::xml_node& n) {
    check(n, {}, {"point", "directional", "spot", "area"});
    for (const pugi::xml_node& l : n.children()) {
        if (l.type() != pugi::node_element) continue;
        const std::string_view kind = l.name();
        if (kind == "point") {
            check(l, {"intensity", "attenuation"}, {"color", "position"});
            PointLight p;
            p.position = xyz_child(l, "position");
            p.intensity = rgb_child(l, "color", RGB{1.f}) * non_negative(l, "intensity", 1.f);
            p.attenuation = non_negative(l, "attenuation", 0.f);
            scene_.lights.points.push_back(p);
        } else if (kind == "directional") {
            check(l, {"intensity"}, {"color", "direction"});
            DirectionalLight d;
            d.direction = direction(l, "direction");
            d.radiance = rgb_child(l, "color", RGB{1.f}) * non_negative(l, "intensity", 1.f);
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
            s.intensity = rgb_child(l, "color", RGB{1.f}) * non_negative(l, "intensity", 1.f);
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
        } else {
            add_area_light(l);
        }
    }
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
        a.radiance = rgb(l.child("radiance")) * non_negative(l, "intensity", 1.f);
    } else {
        a.radiance = rgb_child(l, "color", RGB{1.f}) * non_negative(l, "intensity", 1.f);
    }
    a.samples = count(l, "samples", 16);
    a.sampler = scene_.render.sampler;
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
        a.geometry = add_mesh(std::move(quad), uint32_t(scene_.materials.size() - 1), false);
    }
    scene_.lights.areas.push_back(a);
}

uint32_t Loader::add_mesh(TriangleMesh mesh, uint32_t material, bool smooth) {
    Object o;
    o.kind = ObjectKind::Mesh;
    o.index = uint32_t(scene_.meshes.size());
    o.material = material;
    o.smooth = smooth && !mesh.normals.empty();
    scene_.meshes.push_back(std::move(mesh));
    scene_.objects.push_back(o);
    return uint32_t(scene_.objects.size() - 1);
}

Affine Loader::parse_transform(const pugi::xml_node& object) const {
    Affine xf;
    const pugi::xml_node t = object.child("transform");
    if (!t) return xf;
    check(t, {}, {"translate", "scale", "rotate"});
    // Applied in document order: the first child acts first.
    for (const pugi::xml_node& c : t.children()) {
        if (c.type() != pugi::node_element) continue;
        const std::string_view k = c.name();
        if (k == "translate") {
            xf = Affine::translate(xyz(c)) * xf;
        } else if (k == "scale") {
            check(c, {"x", "y", "z", "s"}, {});
            Vec3 s;
            if (c.attribute("s")) {
                const float v = number(c, "s");
                s = {v, v, v};
            } else {
                s = {number(c, "x"), number(c, "y"), number(c, "z")};
            }
            if (s.x == 0.f || s.y == 0.f || s.z == 0.f) fail(c, "scale factor of zero");
            xf = Affine::scale(s) * xf;
        } else {
            check(c, {"x", "y", "z", "angle"}, {});
            const Vec3 axis{number(c, "x"), number(c, "y"), number(c, "z")};
            if (length_squared(axis) == 0.f) fail(c, "rotation axis is a zero vector");
            xf = Affine::rotate(axis, number(c, "angle")) * xf;
        }
    }
    return xf;
}

uint32_t Loader::parse_material(const pugi::xml_node& object) {
    const pugi::xml_node n = child(object, "material");
    if (std::distance(object.children("material").begin(), object.children("material").end()) > 1)
        fail(n, "an object takes exactly one <material>");
    Material m = material(n, true);
    scene_.materials.push_back(m);
    return uint32_t(scene_.materials.size() - 1);
}

namespace {
struct ConductorPreset {
    const char* name;
    RGB eta, k;
};
// Complex indices of refraction of common metals at roughly 650, 550 and 450 nm.
constexpr ConductorPreset kConductors[] = {
    {"gold", {0.143f, 0.374f, 1.442f}, {3.983f, 2.385f, 1.603f}},
    {"silver", {0.155f, 0.117f, 0.138f}, {4.828f, 3.122f, 2.147f}},
    {"copper", {0.200f, 0.924f, 1.102f}, {3.912f, 2.452f, 2.142f}},
    {"aluminium", {1.657f, 0.880f, 0.521f}, {9.224f, 6.270f, 4.837f}},
};
}  // namespace

Fresnel Loader::conductor_fresnel(const pugi::xml_node& n) const {
    Fresnel f;
    f.kind = FresnelKind::Conductor;
    if (n.attribute("preset")) {
        const std::string p = n.attribute("preset").value();
        for (const ConductorPreset& c : kConductors)
            if (p == c.name) {
                f.eta = c.eta;
                f.k = c.k;
                return f;
            }
        fail(n, "unknown conductor preset '" + p + "' (gold, silver, copper, aluminium)");
    }
    if (n.child("eta") || n.child("k")) {
        f.eta = rgb_child(n, "eta", RGB{1.f});
        f.k = rgb_child(n, "k", RGB{0.f});
        if (!(f.eta.r > 0.f && f.eta.g > 0.f && f.eta.b > 0.f))
            fail(n.child("eta"), "conductor eta must be positive");
        return f;
    }
    // A reflectance r at normal incidence: eta = 1, k = 2 sqrt(r / (1 - r)) gives exactly r
    // there and 1 at grazing angles (pbrt-v4's reading of a "reflectance" conductor).
    const RGB r = rgb_child(n, "reflectance", RGB{1.f});
    auto kk = [](float v) {
        v = std::min(v, 0.9999f);
        return 2.f * std::sqrt(v / (1.f - v));
    };
    if (r.max_component() > 1.f) fail(n.child("reflectance"), "reflectance must be in [0, 1]");
    f.eta = RGB{1.f};
    f.k = {kk(r.r), kk(r.g), kk(r.b)};
    return f;
}

MicrofacetDistribution Loader::distribution(const pugi::xml_node& n, const char* fallback) const {
    const std::string d =
        n.attribute("distribution") ? n.attribute("distribution").value() : fallback;
    if (d == "blinn") {
        float e = 0.f;
        if (n.attribute("exponent"))
            e = positive(n, "exponent", 100.f);
        else {
            // Blinn's exponent with the same RMS slope as a Beckmann roughness alpha.
            const float a = positive(n, "roughness", 0.2f);
            e = std::max(0.f, 2.f / (a * a) - 2.f);
        }
        return MicrofacetDistribution::blinn(e);
    }
    if (d == "beckmann") {
        const float a = positive(n, "roughness", 0.2f);
        if (a > 2.f) fail(n, "roughness must be in (0, 2]");
        return MicrofacetDistribution::beckmann(a);
    }
    if (d == "ashikhmin_shirley" || d == "anisotropic") {
        return MicrofacetDistribution::ashikhmin_shirley(positive(n, "nu", 100.f),
                                                         positive(n, "nv", 100.f));
    }
    fail(n, "unknown distribution '" + d + "' (blinn, beckmann, ashikhmin_shirley)");
}

Material Loader::material(const pugi::xml_node& n, bool top) {
    Material m;
    const std::string type = n.attribute("type").value();
    m.name = type;
    // Attributes and children every physically based material accepts.
    const Names common_children = {"emission"};
    auto with = [](Names a, Names b) {
        std::vector<const char*> v(a.begin(), a.end());
        v.insert(v.end(), b.begin(), b.end());
        return v;
    };
    auto check_v = [&](const std::vector<const char*>& attrs,
                       const std::vector<const char*>& children) {
        for (const pugi::xml_attribute& a : n.attributes())
            if (std::none_of(attrs.begin(), attrs.end(),
                             [&](const char* s) { return std::string_view(s) == a.name(); }))
                fail(n, std::string("unknown attribute '") + a.name() + "' on <material type=\"" +
                            type + "\">");
        for (const pugi::xml_node& c : n.children()) {
            if (c.type() != pugi::node_element) continue;
            if (std::none_of(children.begin(), children.end(),
                             [&](const char* s) { return std::string_view(s) == c.name(); }))
                fail(c, std::string("unknown element <") + c.name() + "> in <material type=\"" +
                            type + "\">");
        }
    };
    auto attrs = [&](Names a) {
        std::vector<const char*> v = with({"type"}, a);
        if (!top) v.push_back("weight");
        return v;
    };
    if (type == "matte" || type == "phong" || type == "reflective" || type == "glass") {
        if (type == "matte") {
            m.type = MaterialType::Matte;
            check_v(attrs({"c_ambient", "c_diffuse"}), with({"base_color"}, common_children));
        } else if (type == "phong") {
            m.type = MaterialType::Phong;
            check_v(attrs({"c_ambient", "c_diffuse", "c_specular", "exp"}),
                    with({"base_color", "specular_color"}, common_children));
        } else if (type == "reflective") {
            m.type = MaterialType::Reflective;
            check_v(attrs({"c_ambient", "c_diffuse", "c_specular", "exp", "c_reflective"}),
                    with({"base_color", "specular_color", "reflective_color"}, common_children));
        } else {
            m.type = MaterialType::Glass;
            check_v(attrs({"ior"}), with({"refraction_color"}, common_children));
        }
        m.c_ambient = non_negative(n, "c_ambient", 0.f);
        m.c_diffuse = non_negative(n, "c_diffuse", m.type == MaterialType::Glass ? 0.f : 1.f);
        m.c_specular = non_negative(n, "c_specular", 1.f);
        m.exponent = positive(n, "exp", 10.f);
        m.c_reflective = non_negative(n, "c_reflective", 1.f);
        m.ior = positive(n, "ior", 1.5f);
        m.base_color =
            rgb_child(n, "base_color", m.type == MaterialType::Glass ? RGB{0.f} : RGB{0.5f});
        m.specular_color = rgb_child(n, "specular_color", RGB{0.f});
        m.reflective_color = rgb_child(n, "reflective_color", RGB{1.f});
        m.refraction_color = rgb_child(n, "refraction_color", RGB{1.f});
        // The physically based reading of the thesis' models.
        if (m.type != MaterialType::Glass && m.c_diffuse > 0.f)
            m.bsdf.add(Lobe::lambert(m.base_color * m.c_diffuse));
        if ((m.type == MaterialType::Phong || m.type == MaterialType::Reflective) &&
            !(m.specular_color * m.c_specular).is_black())
            m.bsdf.add(Lobe::phong(m.specular_color * m.c_specular, m.exponent));
        if (m.type == MaterialType::Reflective)
            m.bsdf.add(Lobe::mirror(m.reflective_color * m.c_reflective, Fresnel{}));
        if (m.type == MaterialType::Glass)
            m.bsdf.add(Lobe::dielectric(m.ior, RGB{1.f}, m.refraction_color));
    } else {
        m.type = MaterialType::Generic;
        m.c_diffuse = 0.f;
        m.base_color = RGB{0.f};
        if (type == "lambert") {
            check_v(attrs({}), with({"reflectance"}, common_children));
            const RGB r = rgb_child(n, "reflectance", RGB{0.5f});
            m.bsdf.add(Lobe::lambert(r));
            m.base_color = r;
            m.c_diffuse = 1.f;
        } else if (type == "oren_nayar") {
            check_v(attrs({"sigma"}), with({"reflectance"}, common_children));
            const RGB r = rgb_child(n, "reflectance", RGB{0.5f});
            const float sigma = non_negative(n, "sigma", 0.3f);
            if (sigma > 1.6f) fail(n, "sigma is in radians and must be at most 1.6");
            m.bsdf.add(Lobe::oren_nayar(r, sigma));
            m.base_color = r;
            m.c_diffuse = 1.f;
        } else if (type == "conductor") {
            check_v(attrs({"preset", "roughness", "distribution", "exponent", "nu", "nv"}),
                    with({"eta", "k", "reflectance"}, common_children));
            const Fresnel f = conductor_fresnel(n);
            const bool rough = n.attribute("roughness") && number(n, "roughness") > 0.f;
            if (rough || n.attribute("distribution"))
                m.bsdf.add(Lobe::microfacet(RGB{1.f}, distribution(n, "beckmann"), f));
            else
                m.bsdf.add(Lobe::mirror(RGB{1.f}, f));
        } else if (type == "dielectric") {
            check_v(attrs({"ior", "roughness"}),
                    with({"reflectance", "transmittance"}, common_children));
            if (n.attribute("roughness") && number(n, "roughness") != 0.f)
                fail(n, "rough dielectrics are not supported (roughness must be 0)");
            m.ior = positive(n, "ior", 1.5f);
            m.bsdf.add(Lobe::dielectric(m.ior, rgb_child(n, "reflectance", RGB{1.f}),
                                        rgb_child(n, "transmittance", RGB{1.f})));
        } else if (type == "microfacet") {
            check_v(attrs({"model", "distribution", "roughness", "exponent", "nu", "nv", "fresnel",
                           "ior", "preset", "kd", "ks"}),
                    with({"specular", "diffuse", "eta", "k", "reflectance"}, common_children));
            const std::string model =
                n.attribute("model") ? n.attribute("model").value() : "torrance_sparrow";
            if (model != "torrance_sparrow" && model != "cook_torrance")
                fail(n,
                     "unknown microfacet model '" + model + "' (torrance_sparrow, cook_torrance)");
            const std::string fk =
                n.attribute("fresnel") ? n.attribute("fresnel").value() : "dielectric";
            Fresnel f;
            if (fk == "dielectric") {
                f.kind = FresnelKind::Dielectric;
                f.ior = positive(n, "ior", 1.5f);
            } else if (fk == "conductor") {
                f = conductor_fresnel(n);
            } else if (fk != "none") {
                fail(n, "unknown fresnel '" + fk + "' (dielectric, conductor, none)");
            }
            const MicrofacetDistribution d =
                distribution(n, model == "cook_torrance" ? "beckmann" : "blinn");
            const float ks = non_negative(n, "ks", 1.f);
            const RGB spec = rgb_child(n, "specular", RGB{1.f}) * ks;
            if (model == "cook_torrance") {
                // Cook–Torrance: kd * Lambert + ks * microfacet specular, kd + ks <= 1.
                const float kd = non_negative(n, "kd", n.child("diffuse") ? 1.f - ks : 0.f);
                if (kd + ks > 1.f + 1e-5f) fail(n, "kd + ks must be at most 1");
                const RGB diff = rgb_child(n, "diffuse", RGB{0.5f}) * kd;
                if (!diff.is_black()) m.bsdf.add(Lobe::lambert(diff));
                m.base_color = diff;
                m.c_diffuse = 1.f;
            } else if (n.child("diffuse") || n.attribute("kd")) {
                fail(n, "a diffuse part belongs to model=\"cook_torrance\" (or use a mix)");
            }
            m.bsdf.add(Lobe::microfacet(spec, d, f));
        } else if (type == "mix") {
            check_v(attrs({}), with({"material"}, common_children));
            float total = 0.f;
            for (const pugi::xml_node& c : n.children("material")) {
                const float w = non_negative(c, "weight", 1.f);
                total += w;
                Material sub = material(c, false);
                if (!sub.emission.is_black())
                    fail(c, "put <emission> on the mix, not on its components");
                sub.bsdf.scale(w);
                for (int i = 0; i < sub.bsdf.size(); ++i)
                    if (!m.bsdf.add(sub.bsdf.lobe(i)))
                        fail(c, "a mix may hold at most " + std::to_string(Bsdf::kMaxLobes) +
                                    " lobes");
                m.base_color += sub.base_color * (w * sub.c_diffuse);
            }
            if (total == 0.f) fail(n, "a mix needs at least one <material> with weight > 0");
            if (total > 1.f + 1e-5f) fail(n, "mix weights sum to more than 1 (energy would grow)");
            m.c_diffuse = 1.f;
        } else {
            fail(n, "unknown material type '" + type +
                        "' (matte, phong, reflective, glass, lambert, oren_nayar, conductor, "
                        "dielectric, microfacet, mix)");
        }
    }
    if (const pugi::xml_node e = n.child("emission")) {
        check(e, {"r", "g", "b", "intensity", "sampling", "two_sided"}, {});
        m.emission =
            rgb(e, {"intensity", "sampling", "two_sided"}) * non_negative(e, "intensity", 1.f);
        m.emission_two_sided = boolean(e, "two_sided", false);
        if (e.attribute("sampling")) {
            const std::string sm = e.attribute("sampling").value();
            if (sm == "area")
                m.emitter_solid_angle = false;
            else if (sm != "solid_angle")
                fail(e, "unknown emitter sampling '" + sm + "' (area, solid_angle)");
        }
    }
    return m;
}

void Loader::parse_objects(const pugi::xml_node& n) {
    check(n, {}, {"triangle_mesh", "sphere", "quad"});
    for (const pugi::xml_node& o : n.children()) {
        if (o.type() != pugi::node_element) continue;
        const std::string_view kind = o.name();
        if (kind == "triangle_mesh") {
            check(o, {"src", "smooth", "name"}, {"material", "transform"});
            const std::string src = o.attribute("src").value();
            if (src.empty()) fail(o, "<triangle_mesh> needs attribute 'src'");
            const std::filesystem::path path = std::filesystem::path(base_) / src;
            if (!std::filesystem::is_regular_file(path))
                fail(o, "mesh file '" + src + "' not found (looked for " + path.string() + ")");
            const Affine xf = parse_transform(o);
            const uint32_t mat = parse_material(o);
            ObjLoadResult r = load_obj(path.string());
            if (r.degenerate_skipped > 0)
                std::fprintf(stderr, "%s:%d: warning: %zu degenerate triangles skipped in %s\n",
                             name_.c_str(), line_of(o), r.degenerate_skipped, src.c_str());
            scene_.skipped_degenerate += r.degenerate_skipped;
            r.mesh.name = o.attribute("name") ? o.attribute("name").value() : src;
            const bool smooth = boolean(o, "smooth", true);
            if (smooth && !r.has_normals) r.mesh.compute_smooth_normals();
            if (!smooth) r.mesh.normals.clear();
            if (!xf.is_identity()) r.mesh.transform(xf);
            add_mesh(std::move(r.mesh), mat, smooth);
        } else if (kind == "quad") {
            check(o, {"name"}, {"corner", "edge1", "edge2", "material", "transform"});
            const Vec3 c = xyz_child(o, "corner"), e1 = xyz_child(o, "edge1"),
                       e2 = xyz_child(o, "edge2");
            if (length_squared(cross(e1, e2)) == 0.f) fail(o, "quad has zero area");
            const Affine xf = parse_transform(o);
            TriangleMesh q;
            q.name = o.attribute("name") ? o.attribute("name").value() : "quad";
            const Vec3 p[4] = {c, c + e1, c + e1 + e2, c + e2};
            for (const Vec3& v : p) q.positions.insert(q.positions.end(), {v.x, v.y, v.z});
            q.indices = {0, 1, 2, 0, 2, 3};
            if (!xf.is_identity()) q.transform(xf);
            add_mesh(std::move(q), parse_material(o), false);
        } else {
            check(o, {"radius", "name"}, {"center", "material", "transform"});
            Sphere s;
            s.center = xyz_child(o, "center");
            s.radius = number(o, "radius");
            if (!(s.radius > 0.f)) fail(o, "sphere radius must be positive");
            const Affine xf = parse_transform(o);
            if (!xf.is_identity()) {
                const Vec3 ax = xf.vector({1, 0, 0}), ay = xf.vector({0, 1, 0}),
                           az = xf.vector({0, 0, 1});
                const float sx = length(ax), sy = length(ay), sz = length(az);
                if (std::fabs(sx - sy) > 1e-5f * sx || std::fabs(sx - sz) > 1e-5f * sx)
                    fail(o, "a sphere takes only uniform scaling");
                s.center = xf.point(s.center);
                s.radius *= sx;
            }
            Object ob;
            ob.kind = ObjectKind::Sphere;
            ob.index = uint32_t(scene_.spheres.size());
            ob.material = parse_material(o);
            scene_.spheres.push_back(s);
            scene_.objects.push_back(ob);
        }
    }
}

}  // namespace

Scene parse_scene(const std::string& xml, const std::string& name, const std::string& base_dir,
                  const RendererOverrides& overrides) {
    return Loader(xml, name, base_dir, overrides).run();
}

Scene load_scene(const std::string& path, const RendererOverrides& overrides) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, 0, "cannot open scene file");
    std::ostringstream ss;
    ss << in.rdbuf();
    const std::string base = std::filesystem::path(path).parent_path().string();
    return parse_scene(ss.str(), path, base.empty() ? "." : base, overrides);
}

}  // namespace foton
