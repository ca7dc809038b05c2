#include "model_scene.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "engine/core/error.h"
#include "engine/core/input_file.h"

namespace foton {

namespace {

// An XML attribute value: the characters XML reads specially, escaped.
std::string attribute_text(const std::string& s) {
    std::string out;
    for (char c : s) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            default:
                out += c;
        }
    }
    return out;
}

constexpr float kFovDegrees = 40.f;

}  // namespace

bool is_model_file(const std::string& path) {
    const std::string ext = lower_extension(path);
    return ext == ".glb" || ext == ".gltf" || ext == ".obj" || ext == ".ply";
}

Scene model_scene(const std::string& path, const RendererOverrides& overrides) {
    const std::filesystem::path p(path);
    const std::string dir = p.parent_path().string();
    // The scene around the model, in foton's XML (so every check of the model's loading is the
    // XML's <triangle_mesh>'s); the camera is placed once the model's bounds are known.
    const std::string xml =
        "<scene><lights><environment intensity=\"1\"/></lights><objects><triangle_mesh src=\"" +
        attribute_text(p.filename().string()) +
        "\"/></objects><film width=\"640\" height=\"480\"/><renderer type=\"path\" "
        "max_depth=\"8\"/><camera fov=\"" +
        std::to_string(kFovDegrees) +
        "\"><eye x=\"0\" y=\"0\" z=\"1\"/><target x=\"0\" y=\"0\" z=\"0\"/></camera></scene>";
    Scene s;
    try {
        s = parse_scene(xml, path, dir.empty() ? "." : dir, overrides);
    } catch (const InputError& e) {
        // The model's own error names the model; the wrapping scene's line 1 would only
        // repeat it ("model.glb:1: model.glb: ...").
        std::string what = e.what();
        for (const std::string& prefix : {e.file() + ":1: ", path + ": "})
            if (what.rfind(prefix, 0) == 0) what = what.substr(prefix.size());
        throw InputError(path, 0, what);
    }
    // A file with lights of its own (glTF's KHR_lights_punctual) is lit by them alone.
    const bool own_lights =
        !s.lights.points.empty() || !s.lights.spots.empty() || !s.lights.directionals.empty();
    if (own_lights) s.environment.reset();
    if (s.model_view) {
        // The file's own camera.
        const ModelView& v = *s.model_view;
        // The file's aspect ratio, 640 pixels wide (--width and --height apply after this,
        // keeping the file's vertical field of view).
        if (v.aspect > 0.f) s.set_resolution(640, std::max(1, int(std::lround(640.f / v.aspect))));
        s.vertical_fov_fixed = true;
        s.camera.eye = v.eye;
        s.camera.target = v.target;
        s.camera.up = v.up;
        if (v.orthographic) s.camera.type = CameraType::Orthographic;
        s.film.pixel_size = v.orthographic
                                ? 2.f * v.half_height / float(s.camera.height)
                                : 2.f * s.camera.d *
                                      std::tan(0.5f * v.vertical_fov_degrees * kPi / 180.f) /
                                      float(s.camera.height);
        s.camera.pixel_size = s.film.pixel_size;
        s.camera.setup();
        s.warnings.push_back(path + ": a model rendered as a scene through its own camera");
        return s;
    }
    const Bounds3 b = s.bounds();
    const Vec3 centre = (b.lo + b.hi) * 0.5f;
    const float radius = std::max(0.5f * length(b.hi - b.lo), 1e-6f);
    // The bounding sphere inside the narrower (vertical) field of view, with a margin.
    const float half = 0.5f * kFovDegrees * kPi / 180.f;
    const float dist = 1.05f * radius / std::sin(half);
    s.camera.eye = centre + normalize(Vec3{0.5f, 0.35f, 1.f}) * dist;
    s.camera.target = centre;
    s.camera.up = {0.f, 1.f, 0.f};
    s.camera.setup();
    s.warnings.push_back(
        path + ": a model rendered as a scene: " + (own_lights ? "its own lights" : "a white sky") +
        ", the path tracer, a camera framing its bounds (put it in an XML scene "
        "for more)");
    return s;
}

}  // namespace foton
