// LightSource and AreaLightSource. Emission spectra other than rgb are taken at luminance
// 1 times "scale", as pbrt-v4 normalises them; "power" and "illuminance" set the scale the
// way pbrt-v4 does for point, spot and distant lights.
#include <cmath>

#include "engine/core/input_file.h"
#include "importer.h"

namespace foton::pbrt {

namespace {

// The illuminance an equal-area map gives a surface facing its pole (+z), texel by texel.
double pole_illuminance(const TextureImage& m) {
    double e = 0.0;
    for (int y = 0; y < m.height; ++y)
        for (int x = 0; x < m.width; ++x) {
            const Vec3 w = equal_area_square_to_sphere(
                {(float(x) + 0.5f) / float(m.width), (float(y) + 0.5f) / float(m.height)});
            const RGB& c = m.texels[std::size_t(y) * std::size_t(m.width) + std::size_t(x)];
            if (w.z > 0.f) e += double(c.luminance()) * double(w.z);
        }
    return e * 4.0 * kPi / (double(m.width) * double(m.height));
}

}  // namespace

void Importer::light_source(const Token& t, const std::string& type, const ParamList& p) {
    const std::string what = "LightSource \"" + type + "\"";
    if (p.real("scale", 1.f) < 0.f) fail(t, what + ": scale must not be negative");
    const float scale = p.real("scale", 1.f) * imaging_ratio();
    // What the light emits, checked: sums of its samples must stay finite (light.h).
    auto emitted = [&](const RGB& v) {
        if (const std::string why = emission_problem(v); !why.empty())
            fail(t, what + ": the emitted colour x scale " + why);
        return v;
    };
    auto photometric = [&](const char* key, float k_e) {
        const float v = p.real(key, -1.f);
        return v > 0.f ? v / k_e : 1.f;
    };
    // A point parameter (the first of its values), or `fallback`.
    auto point = [&](const char* key, Vec3 fallback) {
        const std::vector<Vec3> v = p.triples(key);
        return v.empty() ? fallback : v[0];
    };
    // Spot and distant lights: from "from" towards "to", in world space.
    auto axis = [&]() {
        const Vec3 d = point("to", {0, 0, 1}) - point("from", {0, 0, 0});
        if (length_squared(d) == 0.f) fail(t, what + ": from and to coincide");
        return normalize(gs_.ctm.vector(d));
    };
    if (type == "point") {
        const auto i = p.color("I", true);
        PointLight l;
        l.position = gs_.ctm.point(point("from", {0, 0, 0}));
        l.intensity = emitted((i ? *i : RGB{1.f}) * scale * photometric("power", 4.f * kPi));
        scene_.lights.points.push_back(l);
    } else if (type == "spot") {
        const auto i = p.color("I", true);
        const float cone = p.real("coneangle", 30.f), delta = p.real("conedeltaangle", 5.f);
        if (!(cone > 0.f && cone <= 180.f) || delta < 0.f)
            fail(t, what + ": coneangle must be in (0, 180] and conedeltaangle not negative");
        SpotLight l;
        l.position = gs_.ctm.point(point("from", {0, 0, 0}));
        l.direction = axis();
        l.cos_outer = std::cos(cone * kPi / 180.f);
        l.cos_inner = std::cos(std::max(cone - delta, 0.f) * kPi / 180.f);
        const float k_e = 2.f * kPi * ((1.f - l.cos_inner) + 0.5f * (l.cos_inner - l.cos_outer));
        l.intensity = emitted((i ? *i : RGB{1.f}) * scale * photometric("power", k_e));
        scene_.lights.spots.push_back(l);
    } else if (type == "distant") {
        const auto radiance = p.color("L", true);
        DirectionalLight l;
        l.direction = axis();
        l.radiance =
            emitted((radiance ? *radiance : RGB{1.f}) * scale * photometric("illuminance", 1.f));
        scene_.lights.directionals.push_back(l);
    } else if (type == "infinite") {
        infinite_light(t, p, scale);
    } else {
        fail(t, "unsupported light '" + type + "' (point, spot, distant, infinite)");
    }
    warn_unused(p, what);
    count("LightSource " + type);
}

// pbrt-v4's "infinite" light: a constant L, or an equal-area square image ("filename") in
// the light's frame (its +z is the square's pole); with "portal" (four corners in world
// space) the image, or L, arrives only through that rectangle. "illuminance" scales it to
// that illuminance at a surface facing the light's +z, as pbrt-v4 does. Several infinite
// lights add up.
void Importer::infinite_light(const Token& t, const ParamList& p, float scale) {
    const std::string what = "LightSource \"infinite\"";
    const auto radiance = p.color("L", true);
    const std::string rel = p.text("filename", "");
    if (radiance && !rel.empty()) fail(t, what + ": give \"L\" or \"filename\", not both");
    const std::vector<Vec3> portal = p.triples("portal");
    if (!portal.empty() && portal.size() != 4)
        fail(t, what + ": a portal has 4 corners, not " + std::to_string(portal.size()));
    if (!portal.empty() && !Environment::is_rectangle(portal.data()))
        fail(t, what + ": a portal must be a rectangle (4 corners in order round it)");
    const float illuminance = p.real("illuminance", -1.f);
    const Vec3 up = gs_.ctm.vector({0, 0, 1}), front = gs_.ctm.vector({1, 0, 0});
    if (!(length_squared(cross(up, front)) > 0.f))
        fail(t, what + ": the transformation is degenerate");
    // What the environment classes and the image reader throw, at this line.
    auto made = [&](auto&& make) -> Environment {
        try {
            return make();
        } catch (const InputError& e) {
            fail(t, (rel.empty() ? what : "environment map '" + rel + "'") + ": " + e.what());
        }
        return Environment{};
    };
    std::optional<Environment> env;
    if (rel.empty()) {
        const RGB L = radiance ? *radiance : RGB{1.f};
        // A constant sky of radiance L gives illuminance pi L.
        const float k = illuminance > 0.f && portal.empty() ? illuminance / kPi : 1.f;
        if (const std::string why = emission_problem(L * (scale * k)); !why.empty())
            fail(t, what + ": the emitted colour x scale " + why);
        if (portal.empty()) {
            env = Environment::constant(L * (scale * k));
        } else {
            // pbrt-v4 makes a 1 x 1 image of L for a portal.
            TextureImage one;
            one.width = one.height = 1;
            one.path = file();
            one.texels = {L};
            env = made(
                [&] { return Environment::portal(one, RGB{scale}, up, front, portal.data()); });
        }
    } else {
        const std::string path = input_path(t, "environment map", rel, kMaxMeshFileBytes);
        TextureImage map;
        try {
            map = load_texture_image(path);
        } catch (const InputError& e) {
            fail(t, "environment map '" + rel + "': " + e.what());
        }
        float k = 1.f;
        if (illuminance > 0.f) {
            const double e = pole_illuminance(map);
            if (!(e > 0.0))
                fail(t, what + ": \"illuminance\" given, but the map's upper half is black");
            k = float(double(illuminance) / e);
        }
        env = made([&] {
            return portal.empty()
                       ? Environment::image(std::move(map), EnvMapping::EqualArea, RGB{scale * k},
                                            up, front)
                       : Environment::portal(map, RGB{scale * k}, up, front, portal.data());
        });
    }
    if (scene_.environment)
        scene_.environment->add(*env);
    else
        scene_.environment = std::move(env);
}

void Importer::area_light(const Token& t, const std::string& type, const ParamList& p) {
    if (type != "diffuse") fail(t, "unsupported area light '" + type + "' (diffuse)");
    if (!defining_.empty())
        fail(t, "area lights inside an object definition are not supported (as in pbrt-v4)");
    if (p.has("power")) fail(t, "\"power\" on area lights is not supported: give L and scale");
    if (p.real("scale", 1.f) < 0.f) fail(t, "scale must not be negative");
    const float scale = p.real("scale", 1.f) * imaging_ratio();
    const auto radiance = p.color("L", true);
    gs_.area.texture = -1;
    if (const std::string rel = p.text("filename", ""); !rel.empty()) {
        // pbrt-v4's image area light: the image's RGB at the surface's uv (v up, as
        // pbrt-v4 flips it), times scale: Material::emission_texture.
        if (radiance) fail(t, "AreaLightSource \"diffuse\": give \"L\" or \"filename\", not both");
        Texture tx;
        tx.kind = TextureKind::Image;
        tx.image = image_file(t, rel, false);
        scene_.textures.push_back(tx);
        gs_.area.texture = int32_t(scene_.textures.size() - 1);
    }
    gs_.area.radiance = (radiance ? *radiance : RGB{1.f}) * scale;
    if (const std::string why = emission_problem(gs_.area.radiance); !why.empty())
        fail(t, "AreaLightSource \"diffuse\": the emitted colour x scale " + why);
    gs_.area.two_sided = p.boolean("twosided", false);
    gs_.area.id = area_lights_++;
    warn_unused(p, "AreaLightSource \"diffuse\"");
    count("AreaLightSource diffuse");
}

}  // namespace foton::pbrt
