// The document, film, renderer settings and camera; the public entry points.
#include "loader.h"

namespace foton::xml {

// XML allows one root element and each attribute once per element; pugixml reads a second
// <scene> and the last of two equal attributes without a word, which would make a scene mean
// something other than what a reader of the file sees. Walked without recursion: the nesting
// depth is the file's to choose.
void Loader::reject_duplicates(const pugi::xml_document& doc) const {
    int roots = 0;
    for (const pugi::xml_node& c : doc.children())
        if (c.type() == pugi::node_element && ++roots > 1)
            fail(c, std::string("a second root element <") + c.name() +
                        "> (a file holds one <scene>)");
    pugi::xml_node n = doc.first_child();
    while (n) {
        if (n.type() == pugi::node_element)
            for (pugi::xml_attribute a = n.first_attribute(); a; a = a.next_attribute())
                for (pugi::xml_attribute b = a.next_attribute(); b; b = b.next_attribute())
                    if (std::string_view(a.name()) == b.name())
                        fail(n, std::string("attribute '") + a.name() + "' given twice on <" +
                                    n.name() + ">");
        if (n.first_child()) {
            n = n.first_child();
            continue;
        }
        while (n && !n.next_sibling()) n = n.parent();
        if (n) n = n.next_sibling();
    }
}

Scene Loader::run() {
    pugi::xml_document doc;
    const pugi::xml_parse_result r = doc.load_buffer(xml_.data(), xml_.size());
    if (!r)
        throw InputError(name_, line_of(r.offset),
                         std::string("malformed XML: ") + r.description());
    reject_duplicates(doc);
    const pugi::xml_node root = doc.document_element();
    if (std::string_view(root.name()) != "scene")
        fail(root, std::string("root element must be <scene>, not <") + root.name() + ">");
    check(root, {},
          {"background", "ambient", "lights", "aggregate", "objects", "film", "renderer", "camera",
           "media"});
    scene_.source = name_;
    for (const char* once : {"background", "ambient", "lights", "aggregate", "objects", "film",
                             "renderer", "camera", "media"}) {
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
        check(n, {"type", "density", "lazy"}, {});
        if (!parse_accel(n.attribute("type").value(), scene_.accel))
            fail(n, std::string("unknown aggregate type '") + n.attribute("type").value() +
                        "' (brute, brute-simd, grid, bvh, embree, octree, kdtree)");
        scene_.grid_density = positive(n, "density", scene_.grid_density);
        scene_.grid_lazy = boolean(n, "lazy", false);
    }
    // Media before the camera and the objects, which name them.
    if (const auto n = root.child("media")) parse_media(n);
    parse_camera(child(root, "camera"));
    if (const auto n = root.child("lights")) parse_lights(n);
    if (scene_.environment && root.child("background"))
        fail(root.child("background"),
             "give a <background> colour or an <environment> light, not both");
    parse_objects(child(root, "objects"));
    bool has_geometry = false;
    for (const Object& o : scene_.objects)
        if (scene_.materials[o.material].type != MaterialType::Emitter) has_geometry = true;
    if (!has_geometry) fail(root.child("objects"), "the scene has no objects");
    scene_.check_extent();
    return std::move(scene_);
}

void Loader::parse_film(const pugi::xml_node& n) {
    check(n,
          {"width", "height", "size", "gamma", "max_sample_value", "filter", "filter_radius",
           "filter_sigma", "filter_b", "filter_c", "filter_tau"},
          {});
    FilmSettings& f = scene_.film;
    f.width = int(count(n, "width", 512));
    f.height = int(count(n, "height", 512));
    check_image_size(f.width, f.height, name_, line_of(n));
    f.full_width = f.width;
    f.full_height = f.height;
    f.pixel_size = positive(n, "size", 0.001f);
    f.gamma = positive(n, "gamma", 2.2f);
    if (n.attribute("max_sample_value")) f.max_sample_value = positive(n, "max_sample_value", 1.f);
    // The pixel filter (pixel_filter.h), the thesis' 1-pixel box unless asked; radii as
    // pbrt-v4's defaults.
    const std::string filter = n.attribute("filter") ? n.attribute("filter").value() : "box";
    FilterType kind;
    if (!parse_filter_type(filter, kind))
        fail(n, "unknown filter '" + filter + "' (" + kFilterTypeList + ")");
    const float r = positive(n, "filter_radius", default_filter_radius(kind));
    if (r > 16.f) fail(n, "filter_radius must be at most 16 pixels");
    // Each shape parameter belongs to one type.
    const struct {
        const char* attribute;
        FilterType owner;
    } own[] = {{"filter_sigma", FilterType::Gaussian},
               {"filter_b", FilterType::Mitchell},
               {"filter_c", FilterType::Mitchell},
               {"filter_tau", FilterType::Lanczos}};
    for (const auto& o : own)
        if (n.attribute(o.attribute) && o.owner != kind)
            fail(n, std::string(o.attribute) + " belongs to filter=\"" + filter_type_name(o.owner) +
                        "\"");
    FilterShape shape;
    shape.sigma = positive(n, "filter_sigma", shape.sigma);
    shape.tau = positive(n, "filter_tau", shape.tau);
    shape.b = n.attribute("filter_b").as_float(shape.b);
    shape.c = n.attribute("filter_c").as_float(shape.c);
    if (!(shape.b >= 0.f && shape.b <= 1.f && shape.c >= 0.f && shape.c <= 1.f))
        fail(n, "filter_b and filter_c must be in [0, 1]");
    f.filter = PixelFilter::make(kind, r, r, shape);
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
    scene_.renderer = std::move(params);
}

void Loader::parse_camera(const pugi::xml_node& n) {
    check(n, {"type", "d", "exposure", "fov", "lens_radius", "focal_distance", "medium"},
          {"eye", "target", "up"});
    Camera& c = scene_.camera;
    const std::string type = n.attribute("type") ? n.attribute("type").value() : "perspective";
    if (type == "perspective")
        c.type = CameraType::Perspective;
    else if (type == "orthographic")
        c.type = CameraType::Orthographic;
    else if (type == "equirectangular" || type == "panoramic")
        c.type = CameraType::Equirectangular;
    else if (type == "fisheye")
        c.type = CameraType::Fisheye;
    else
        fail(n, "unknown camera type '" + type +
                    "' (perspective, orthographic, equirectangular, fisheye)");
    if (c.type == CameraType::Fisheye) {
        // The field of view across the image diagonal, in degrees (default 180).
        const float fov = n.attribute("fov") ? number(n, "fov") : 180.f;
        if (!(fov > 0.f && fov <= 360.f)) fail(n, "a fisheye's fov must be in (0, 360] degrees");
        c.fisheye_fov = fov * kPi / 180.f;
    }
    c.eye = xyz_child(n, "eye");
    c.target = xyz_child(n, "target");
    c.up = n.child("up") ? xyz_child(n, "up") : Vec3{0, 1, 0};
    c.d = positive(n, "d", 1.f);
    c.exposure = positive(n, "exposure", 1.f);
    c.width = scene_.film.width;
    c.height = scene_.film.height;
    if (n.attribute("fov") && c.type != CameraType::Fisheye) {
        // Convenience: a vertical field of view in degrees sets the pixel size.
        const float fov = number(n, "fov");
        if (!(fov > 0.f && fov < 180.f)) fail(n, "fov must be in (0, 180) degrees");
        if (c.type != CameraType::Perspective) fail(n, "fov applies to perspective cameras only");
        scene_.film.pixel_size = 2.f * c.d * std::tan(0.5f * fov * kPi / 180.f) / float(c.height);
    }
    c.pixel_size = scene_.film.pixel_size;
    if (length_squared(c.target - c.eye) == 0.f) fail(n, "camera eye and target coincide");
    c.lens_radius = non_negative(n, "lens_radius", 0.f);
    scene_.camera_medium = medium_ref(n, "medium");
    c.focal_distance = positive(n, "focal_distance", length(c.target - c.eye));
    if (c.lens_radius > 0.f && c.type != CameraType::Perspective)
        fail(n, "a thin lens (lens_radius) needs a perspective camera");
    if (length_squared(cross(c.target - c.eye, c.up)) == 0.f)
        fail(n, "camera up is parallel to the viewing direction");
    c.setup();
}

}  // namespace foton::xml

namespace foton {

Scene parse_scene(const std::string& xml, const std::string& name, const std::string& base_dir,
                  const RendererOverrides& overrides) {
    return xml::Loader(xml, name, base_dir, overrides).run();
}

}  // namespace foton
