// Files, tokens, parameter lists, the directives that shape the graphics state, and the
// public entry points.
#include "importer.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "engine/core/decompress.h"
#include "engine/core/input_file.h"
#include "engine/scene/pbrt_loader.h"

namespace foton::pbrt {

Importer::Importer(std::string path, std::string text, std::string base_dir,
                   const RendererOverrides& overrides)
    : base_(std::move(base_dir)), overrides_(overrides) {
    files_.push_back(std::make_unique<Tokenizer>(std::move(text), path));
    scene_.source = path;
    renderer_.file = path;
    // pbrt-v4's defaults where they differ from foton's own.
    renderer_.set("type", "path", path, 0);
    renderer_.set("spp", "16", path, 0);
    renderer_.set("max_depth", "5", path, 0);
    Material diffuse;
    diffuse.type = MaterialType::Generic;
    diffuse.name = "diffuse";
    diffuse.base_color = RGB{0.5f};
    diffuse.bsdf.add(Lobe::lambert(RGB{0.5f}));
    materials_.push_back(diffuse);
}

Token Importer::next() {
    for (;;) {
        Token t = files_.back()->next();
        if (t.kind != TokenKind::End || files_.size() == 1) return t;
        files_.pop_back();  // an included file ended: go on with the one that included it
    }
}

void Importer::warn(const std::string& where, int line, const std::string& what) {
    warnings_.push_back(where + ":" + std::to_string(line) + ": " + what);
}

void Importer::warn_unused(const ParamList& p, const std::string& what) {
    for (std::string& w : p.unused(what)) warnings_.push_back(std::move(w));
}

void Importer::include(const Token& t) {
    const Token name = expect_string(t, "a file name");
    if (files_.size() >= std::size_t(kMaxIncludeDepth))
        fail(t, "includes nest more than " + std::to_string(kMaxIncludeDepth) + " deep");
    // An included file holds geometry as often as directives (pbrt-v4-scenes' hair is a
    // gzipped file of curves): the mesh files' size limit, and .gz or .xz decompressed.
    const std::string path =
        input_path(t, std::string(t.text), std::string(name.text), kMaxMeshFileBytes);
    count(std::string(t.text));
    files_.push_back(std::make_unique<Tokenizer>(
        read_input_file_decompressed(path, kMaxMeshFileBytes, "scene file"), path));
}

std::string Importer::input_path(const Token& t, const std::string& what, const std::string& rel,
                                 uint64_t max_bytes) {
    // An absolute `rel` replaces the base in operator/.
    const std::string path = (std::filesystem::path(base_) / rel).string();
    const std::string problem = input_file_problem(path, max_bytes);
    if (!problem.empty())
        fail(t, what + " '" + rel + "': " + (problem == "not found" ? "file not found" : problem) +
                    " (looked for " + path + ")");
    return path;
}

void Importer::apply(const Affine& xf, bool replace) {
    if (!transform_start_) return;  // only the shutter's end moves: foton renders the start
    gs_.ctm = replace ? xf : gs_.ctm * xf;
}

namespace {

Affine look_at(const Vec3& eye, const Vec3& at, const Vec3& up, bool& ok) {
    // pbrt's LookAt: camera from world, with the camera's +z towards `at` and +x to the
    // right of `up` in its left-handed frame.
    const Vec3 dir = normalize(at - eye);
    ok = length_squared(at - eye) > 0.f && length_squared(cross(normalize(up), dir)) > 0.f;
    if (!ok) return Affine{};
    const Vec3 right = normalize(cross(normalize(up), dir));
    const Vec3 new_up = cross(dir, right);
    Affine world_from_camera;
    const Vec3 cols[3] = {right, new_up, dir};
    for (int j = 0; j < 3; ++j) {
        world_from_camera.m[0][j] = cols[j].x;
        world_from_camera.m[1][j] = cols[j].y;
        world_from_camera.m[2][j] = cols[j].z;
    }
    world_from_camera.m[0][3] = eye.x;
    world_from_camera.m[1][3] = eye.y;
    world_from_camera.m[2][3] = eye.z;
    return world_from_camera.inverse();
}

}  // namespace

void Importer::directive(const Token& t) {
    const std::string d(t.text);
    auto numbers = [&](int n) {
        std::vector<float> v;
        const bool bracket = files_.back()->peek().kind == TokenKind::Open;
        if (bracket) files_.back()->next();
        for (int i = 0; i < n; ++i) v.push_back(expect_number(t));
        if (bracket && files_.back()->next().kind != TokenKind::Close)
            fail(t, d + ": expected ']' after " + std::to_string(n) + " numbers");
        return v;
    };
    auto matrix = [&]() {
        const std::vector<float> v = numbers(16);
        // The 16 numbers are the matrix column by column; the last row must be 0 0 0 1.
        if (v[3] != 0.f || v[7] != 0.f || v[11] != 0.f || v[15] != 1.f)
            fail(t, d + ": projective matrices are not supported (the last row must be 0 0 0 1)");
        Affine a;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 4; ++j) a.m[i][j] = v[std::size_t(4 * j + i)];
        return a;
    };
    auto singular = [&](const Affine& a) {
        if (!(std::fabs(a.determinant()) > 0.f)) fail(t, d + ": the transform is singular");
        return a;
    };
    if (d == "Include" || d == "Import") {
        include(t);
    } else if (d == "WorldBegin") {
        if (in_world_) fail(t, "WorldBegin given twice");
        in_world_ = true;
        gs_.ctm = Affine{};
        coordinate_systems_["world"] = Affine{};
    } else if (d == "WorldEnd") {
        warn(file(), t.line, "WorldEnd is pbrt-v3 syntax (ignored)");
    } else if (d == "AttributeBegin" || d == "TransformBegin") {
        if (stack_.size() >= 100000) fail(t, d + " nests too deep");
        stack_.push_back(gs_);
        stack_kind_.push_back(d == "AttributeBegin" ? 'a' : 't');
    } else if (d == "AttributeEnd" || d == "TransformEnd") {
        if (stack_.empty()) fail(t, d + " without a matching begin");
        const char want = d == "AttributeEnd" ? 'a' : 't';
        if (stack_kind_.back() != want) fail(t, d + " closes a block of the other kind");
        if (want == 'a') {
            gs_ = stack_.back();
        } else {
            gs_.ctm = stack_.back().ctm;
        }
        stack_.pop_back();
        stack_kind_.pop_back();
    } else if (d == "Identity") {
        apply(Affine{}, true);
    } else if (d == "Translate") {
        const auto v = numbers(3);
        apply(Affine::translate({v[0], v[1], v[2]}));
    } else if (d == "Scale") {
        const auto v = numbers(3);
        apply(singular(Affine::scale({v[0], v[1], v[2]})));
    } else if (d == "Rotate") {
        const auto v = numbers(4);
        if (v[1] == 0.f && v[2] == 0.f && v[3] == 0.f) fail(t, "Rotate about a zero axis");
        apply(Affine::rotate({v[1], v[2], v[3]}, v[0]));
    } else if (d == "LookAt") {
        const auto v = numbers(9);
        bool ok = false;
        const Affine a = look_at({v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}, ok);
        if (!ok) fail(t, "LookAt: eye equals target, or up is parallel to the view direction");
        apply(a);
    } else if (d == "Transform") {
        apply(singular(matrix()), true);
    } else if (d == "ConcatTransform") {
        apply(singular(matrix()));
    } else if (d == "CoordinateSystem") {
        coordinate_systems_[std::string(expect_string(t, "a name").text)] = gs_.ctm;
    } else if (d == "CoordSysTransform") {
        const std::string name(expect_string(t, "a name").text);
        const auto it = coordinate_systems_.find(name);
        if (it == coordinate_systems_.end()) fail(t, "unknown coordinate system '" + name + "'");
        apply(it->second, true);
    } else if (d == "ActiveTransform") {
        const Token w = next();
        if (w.text == "All") {
            transform_start_ = true;
        } else if (w.text == "StartTime") {
            transform_start_ = true;
            warn(file(), t.line,
                 "ActiveTransform StartTime: motion blur is not supported, the transforms that "
                 "follow move the start pose only, which is rendered");
        } else if (w.text == "EndTime") {
            transform_start_ = false;
            warn(file(), t.line,
                 "ActiveTransform EndTime: motion blur is not supported, the transforms that "
                 "follow are ignored until StartTime or All (the start transform is rendered)");
        } else {
            fail(t, "ActiveTransform takes StartTime, EndTime or All");
        }
    } else if (d == "TransformTimes") {
        numbers(2);
        warn(file(), t.line, "TransformTimes: motion blur is not supported (ignored)");
    } else if (d == "ReverseOrientation") {
        gs_.reverse = !gs_.reverse;
    } else if (d == "Option") {
        read_params();
        warn(file(), t.line, "Option is not supported (ignored)");
    } else if (d == "ColorSpace") {
        const std::string cs(expect_string(t, "a colour space").text);
        if (cs != "srgb") fail(t, "only the srgb colour space is supported, not '" + cs + "'");
    } else if (d == "Attribute") {
        expect_string(t, "a target");
        const ParamList p = read_params();
        if (!p.params.empty()) fail(t, "Attribute defaults are not supported");
    } else if (d == "Camera" || d == "Film" || d == "Sampler" || d == "Integrator" ||
               d == "PixelFilter" || d == "Accelerator") {
        if (in_world_) fail(t, d + " belongs before WorldBegin");
        const std::string type(expect_string(t, "a type").text);
        const ParamList p = read_params();
        if (d == "Camera") camera(t, type, p);
        if (d == "Film") film(t, type, p);
        if (d == "Sampler") sampler(t, type, p);
        if (d == "Integrator") integrator(t, type, p);
        if (d == "PixelFilter") pixel_filter(t, type, p);
        if (d == "Accelerator") {
            warn(file(), t.line, "Accelerator '" + type + "' ignored (foton's bvh, or --accel)");
            for (const Param& q : p.params) q.used = true;
        }
    } else if (d == "MakeNamedMedium") {
        const std::string name(expect_string(t, "a name").text);
        make_named_medium(t, name, read_params());
    } else if (d == "MediumInterface") {
        medium_interface(t);
    } else if (d == "Material") {
        const std::string type(expect_string(t, "a type").text);
        materials_.push_back(make_material(t, type, read_params()));
        gs_.material = uint32_t(materials_.size() - 1);
    } else if (d == "MakeNamedMaterial") {
        const std::string name(expect_string(t, "a name").text);
        ParamList p = read_params();
        const std::string type = p.text("type", "");
        if (type.empty()) fail(t, "MakeNamedMaterial '" + name + "' needs \"string type\"");
        materials_.push_back(make_material(t, type, p));
        materials_.back().name = name;
        named_materials_[name] = uint32_t(materials_.size() - 1);
    } else if (d == "NamedMaterial") {
        const std::string name(expect_string(t, "a name").text);
        const auto it = named_materials_.find(name);
        if (it == named_materials_.end()) fail(t, "unknown named material '" + name + "'");
        gs_.material = it->second;
    } else if (d == "Texture") {
        const std::string name(expect_string(t, "a name").text);
        const std::string kind(expect_string(t, "a kind (spectrum or float)").text);
        const std::string type(expect_string(t, "a type").text);
        texture(t, name, kind, type, read_params());
    } else if (d == "LightSource") {
        const std::string type(expect_string(t, "a type").text);
        light_source(t, type, read_params());
    } else if (d == "AreaLightSource") {
        const std::string type(expect_string(t, "a type").text);
        area_light(t, type, read_params());
    } else if (d == "Shape") {
        const std::string type(expect_string(t, "a type").text);
        shape(t, type, read_params());
    } else if (d == "ObjectBegin") {
        if (!defining_.empty()) fail(t, "ObjectBegin inside the definition of '" + defining_ + "'");
        defining_ = std::string(expect_string(t, "a name").text);
        if (prototypes_.count(defining_)) fail(t, "object '" + defining_ + "' defined twice");
        proto_ = &prototypes_[defining_];
        stack_.push_back(gs_);
        stack_kind_.push_back('a');
    } else if (d == "ObjectEnd") {
        if (defining_.empty()) fail(t, "ObjectEnd without ObjectBegin");
        defining_.clear();
        proto_ = nullptr;
        gs_ = stack_.back();
        stack_.pop_back();
        stack_kind_.pop_back();
    } else if (d == "ObjectInstance") {
        object_instance(t, std::string(expect_string(t, "a name").text));
    } else if (t.kind == TokenKind::Word) {
        fail(t, "unknown directive '" + d + "'");
    } else {
        fail(t, "expected a directive, got '" + d + "'");
    }
}

Scene Importer::run() {
    for (;;) {
        const Token t = next();
        if (t.kind == TokenKind::End) break;
        directive(t);
    }
    if (!defining_.empty())
        throw InputError(file(), 0, "ObjectBegin '" + defining_ + "' not closed");
    if (!stack_.empty())
        throw InputError(file(), 0, "AttributeBegin or TransformBegin without its end");
    if (scene_.objects.empty()) throw InputError(file(), 0, "the scene has no shapes");
    scene_.check_extent();
    finish_camera();
    scene_.camera_medium = medium_id(camera_medium_, camera_medium_file_, camera_medium_line_);
    for (Medium& m : scene_.media) {
        m.Le *= imaging_ratio();
        m.le_factor *= imaging_ratio();
    }
    // pbrt-v4's default integrator is volpath: a scene with media and no Integrator gets it.
    if (scene_.volumetric() && integrator_line_ == 0)
        renderer_.set("type", "volpath", scene_.volumetric_file, scene_.volumetric_line);
    for (const auto& [key, value] : overrides_) renderer_.set(key, value, "--set", 0);
    if (glass_line_ > 0 &&
        !(renderer_.text("type") == "volpath" && renderer_.boolean("spectral", false)))
        warn(glass_file_, glass_line_,
             glass_name_ +
                 " disperses only in spectral volpath (--set type=volpath --set "
                 "spectral=true): this render uses its d-line index");
    scene_.renderer = std::move(renderer_);
    scene_.warnings = std::move(warnings_);
    for (const auto& [what, n] : imported_)
        scene_.imported.push_back(what + (n > 1 ? " x" + std::to_string(n) : ""));
    return std::move(scene_);
}

}  // namespace foton::pbrt

namespace foton {

Scene parse_pbrt_scene(const std::string& text, const std::string& name,
                       const std::string& base_dir, const RendererOverrides& overrides) {
    return pbrt::Importer(name, text, base_dir, overrides).run();
}

}  // namespace foton
