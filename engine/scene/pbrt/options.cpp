// Camera, Film, Sampler, Integrator and PixelFilter: pbrt-v4's rendering options as
// foton's camera, film and renderer settings.
#include <cmath>
#include <sstream>

#include "importer.h"

namespace foton::pbrt {

void Importer::camera(const Token& t, const std::string& type, const ParamList& p) {
    if (type != "perspective" && type != "orthographic")
        fail(t, "unsupported camera '" + type + "' (perspective, orthographic)");
    camera_type_ = type;
    camera_line_ = t.line;
    // pbrt-v4: the camera sits in the current MediumInterface's outside medium.
    camera_medium_ = gs_.medium_outside;
    camera_medium_file_ = gs_.medium_file;
    camera_medium_line_ = gs_.medium_line;
    camera_file_ = file();
    camera_from_world_ = gs_.ctm;
    coordinate_systems_["camera"] = gs_.ctm.inverse();
    if (type == "perspective") {
        fov_ = p.real("fov", 90.f);
        if (!(fov_ > 0.f && fov_ < 180.f)) fail(t, "fov must be in (0, 180) degrees");
    }
    lens_radius_ = p.real("lensradius", 0.f);
    focal_distance_ = p.real("focaldistance", 1e6f);
    if (lens_radius_ < 0.f || !(focal_distance_ > 0.f))
        fail(t, "lensradius must not be negative and focaldistance must be positive");
    if (lens_radius_ > 0.f && type != "perspective")
        fail(t, "a thin lens (lensradius) needs a perspective camera");
    const std::vector<float> sw = p.reals("screenwindow");
    if (!sw.empty()) {
        if (sw.size() != 4 || !(sw[1] > sw[0]) || !(sw[3] > sw[2]))
            fail(t, "screenwindow takes four numbers: xmin xmax ymin ymax");
        screen_window_ = sw;
    }
    // The shutter interval is the sensor's exposure time (no motion blur is rendered).
    const float open = p.real("shutteropen", 0.f), close = p.real("shutterclose", 1.f);
    if (!(close > open)) fail(t, "shutterclose must be after shutteropen");
    exposure_time_ = close - open;
    warn_unused(p, "Camera \"" + type + "\"");
    count("Camera " + type);
}

void Importer::film(const Token& t, const std::string& type, const ParamList& p) {
    if (type != "rgb" && type != "gbuffer" && type != "spectral")
        fail(t, "unsupported film '" + type + "' (rgb)");
    if (type != "rgb") warn(file(), t.line, "Film \"" + type + "\" is rendered as an rgb film");
    // The sensor: the imaging ratio's ISO; pbrt-v4's default sensor (cie1931) alone.
    iso_ = p.real("iso", 100.f);
    if (!(iso_ > 0.f)) fail(t, "iso must be positive");
    const std::string sensor = p.text("sensor", "cie1931");
    if (sensor != "cie1931")
        warn(file(), t.line,
             "Film sensor \"" + sensor + "\" is rendered with the cie1931 sensor (XYZ matching)");
    if (p.real("whitebalance", 0.f) != 0.f)
        warn(file(), t.line, "Film whitebalance ignored (no chromatic adaptation)");
    // pbrt-v4's clamp of each sample's largest channel (default: none).
    if (p.has("maxcomponentvalue")) {
        scene_.film.max_sample_value = p.real("maxcomponentvalue", 0.f);
        if (!(scene_.film.max_sample_value > 0.f)) fail(t, "maxcomponentvalue must be positive");
    }
    width_ = p.integer("xresolution", 1280);
    height_ = p.integer("yresolution", 720);
    if (width_ < 1 || height_ < 1) fail(t, "xresolution and yresolution must be positive");
    check_image_size(width_, height_, file(), t.line);
    if (p.has("filename"))
        warn(file(), t.line,
             "Film filename '" + p.text("filename", "") +
                 "' ignored: foton writes out/<scene>.exr, or the file given by -o");
    const std::vector<float> cw = p.reals("cropwindow");
    if (!cw.empty()) {
        if (cw.size() != 4 || !(cw[0] >= 0.f && cw[0] < cw[1] && cw[1] <= 1.f && cw[2] >= 0.f &&
                                cw[2] < cw[3] && cw[3] <= 1.f))
            fail(t, "cropwindow takes x0 x1 y0 y1 with 0 <= x0 < x1 <= 1 and 0 <= y0 < y1 <= 1");
        crop_ = {int(std::ceil(float(width_) * cw[0])), int(std::ceil(float(width_) * cw[1])),
                 int(std::ceil(float(height_) * cw[2])), int(std::ceil(float(height_) * cw[3]))};
    }
    const std::vector<int> pb = p.integers("pixelbounds");
    if (!pb.empty()) {
        if (pb.size() != 4 || !(pb[0] >= 0 && pb[0] < pb[1] && pb[1] <= width_ && pb[2] >= 0 &&
                                pb[2] < pb[3] && pb[3] <= height_))
            fail(t, "pixelbounds takes x0 x1 y0 y1 within the image");
        crop_ = {pb[0], pb[1], pb[2], pb[3]};
    }
    warn_unused(p, "Film \"" + type + "\"");
    count("Film " + type);
}

void Importer::sampler(const Token& t, const std::string& type, const ParamList& p) {
    int spp = p.integer("pixelsamples", 16);
    if (type == "stratified") {
        const int xs = p.integer("xsamples", 4), ys = p.integer("ysamples", 4);
        if (xs < 1 || ys < 1) fail(t, "xsamples and ysamples must be positive");
        spp = xs * ys;
        renderer_.set("sampler", p.boolean("jitter", true) ? "jittered" : "regular", file(),
                      t.line);
    } else if (type == "independent") {
        renderer_.set("sampler", "random", file(), t.line);
    } else if (type == "halton" || type == "sobol" || type == "zsobol" || type == "paddedsobol") {
        // foton's own low-discrepancy samplers; paddedsobol's per-dimension padding is
        // rendered with the Sobol' sampler's (global) sequence.
        const std::string ours = type == "paddedsobol" ? "sobol" : type;
        if (type == "paddedsobol")
            warn(file(), t.line, "Sampler \"paddedsobol\" is rendered with foton's sobol sampler");
        renderer_.set("sampler", ours, file(), t.line);
        // pbrt-v4 scrambles by default (Owen for the Sobol' family, digit permutations for
        // Halton), as foton always does; other randomizations are not available.
        const std::string def = type == "halton" ? "permutedigits" : "fastowen";
        const std::string r = p.text("randomization", def);
        const bool same = r == def || (type != "halton" && r == "owen");
        if (!same)
            warn(file(), t.line,
                 "Sampler \"" + type + "\": randomization \"" + r + "\" is rendered with foton's " +
                     (type == "halton" ? "digit permutations" : "Owen scrambling"));
    } else if (type == "pmj02bn") {
        warn(file(), t.line,
             "Sampler \"pmj02bn\" is not available: foton's jittered sampler is used");
        renderer_.set("sampler", "jittered", file(), t.line);
    } else {
        fail(t, "unknown sampler '" + type + "'");
    }
    if (spp < 1) fail(t, "pixelsamples must be positive");
    renderer_.set("spp", std::to_string(spp), file(), t.line);
    if (p.has("seed")) renderer_.set("seed", std::to_string(p.integer("seed", 0)), file(), t.line);
    warn_unused(p, "Sampler \"" + type + "\"");
    count("Sampler " + type);
}

namespace {

std::string number_text(const Param& q) {
    std::ostringstream s;
    s.precision(9);
    if (!q.strings.empty()) return q.strings[0];
    s << q.numbers[0];
    return s.str();
}

}  // namespace

void Importer::integrator(const Token& t, const std::string& type, const ParamList& p) {
    const std::string here = file();
    integrator_line_ = t.line;
    auto depth = [&] {
        const int d = p.integer("maxdepth", 5);
        if (d < 0) fail(t, "maxdepth must not be negative");
        renderer_.set("max_depth", std::to_string(d), here, t.line);
    };
    if (type == "bdpt") {
        // foton has pbrt-v4's bidirectional path tracer's estimator (all strategies, MIS).
        renderer_.set("type", "bdpt", here, t.line);
        depth();
        for (const char* debug : {"visualizestrategies", "visualizeweights"})
            if (p.has(debug) && p.boolean(debug, false))
                warn(here, t.line,
                     std::string(debug) +
                         " ignored (foton's bdpt writes one image; its "
                         "strategy setting shows one (s, t) technique)");
        if (p.has("regularize") && p.boolean("regularize", false))
            warn(here, t.line, "regularize ignored (foton regularises in path and volpath only)");
        if (p.has("lightsampler") && p.text("lightsampler", "bvh") != "power")
            warn(here, t.line, "lightsampler ignored: foton chooses lights by power");
    } else if (type == "mlt") {
        // Both mutate bidirectional paths in primary sample space; pbrt-v4's chains carry one
        // (s, t) strategy each, foton's every strategy of a pair of subpaths (Kelemen's):
        // the same expected image, other noise.
        warn(here, t.line,
             "Integrator \"mlt\" is rendered with foton's mlt over bdpt paths, all strategies "
             "of a pair of subpaths per sample (pbrt-v4's mutates bdpt paths one strategy at a "
             "time; the same expected image)");
        renderer_.set("type", "mlt", here, t.line);
        renderer_.set("mlt_paths", "bdpt", here, t.line);
        depth();
        auto pass_on = [&](const char* key, const char* ours, bool integer) {
            if (!p.has(key)) return;
            renderer_.set(
                ours,
                integer ? std::to_string(p.integer(key, 0)) : std::to_string(p.real(key, 0.f)),
                here, t.line);
        };
        pass_on("bootstrapsamples", "mlt_bootstrap", true);
        pass_on("chains", "mlt_chains", true);
        pass_on("mutationsperpixel", "spp", true);
        pass_on("largestepprobability", "large_step", false);
        pass_on("sigma", "mlt_sigma", false);
        if (p.has("regularize") && p.boolean("regularize", false))
            warn(here, t.line, "regularize ignored (foton regularises in path and volpath only)");
    } else if (type == "path" || type == "volpath" || type == "simplepath" ||
               type == "randomwalk" || type == "simplevolpath") {
        // volpath is foton's volpath; the other unidirectional ones its path tracer (the same
        // expected image).
        const bool volumetric = type.find("vol") != std::string::npos;
        if (type != "path" && type != "volpath")
            warn(here, t.line,
                 "Integrator \"" + type + "\" is rendered with foton's " +
                     (volumetric ? "volpath" : "path tracer") + " (the same expected image)");
        renderer_.set("type", volumetric ? "volpath" : "path", here, t.line);
        depth();
        // pbrt-v4's path regularisation, which foton's path tracer and volpath have.
        if (p.has("regularize"))
            renderer_.set("regularize", p.boolean("regularize", false) ? "true" : "false", here,
                          t.line);
        // pbrt-v4's light samplers are foton's light_selection (its default is the BVH).
        std::string sampler = p.text("lightsampler", "bvh");
        if (sampler == "exhaustive") {
            warn(here, t.line,
                 "lightsampler \"exhaustive\" is rendered with \"bvh\" (the same tree; "
                 "foton does not sum over every light)");
            sampler = "bvh";
        }
        if (sampler != "bvh" && sampler != "power" && sampler != "uniform")
            fail(t, "lightsampler \"" + sampler + "\": expected bvh, power, uniform or exhaustive");
        renderer_.set("light_selection", sampler, here, t.line);
        for (const char* other :
             {"bootstrapsamples", "chains", "mutationsperpixel", "largestepprobability", "sigma",
              "visualizestrategies", "visualizeweights", "samplelights", "samplebsdf"})
            if (p.has(other)) warn(here, t.line, std::string(other) + " ignored");
    } else if (type == "lighttracer") {
        renderer_.set("type", "light", here, t.line);
        depth();
    } else if (type == "sppm") {
        renderer_.set("type", "sppm", here, t.line);
        depth();
        renderer_.set("spp", std::to_string(p.integer("iterations", 64)), here, t.line);
        if (p.has("photonsperiteration"))
            renderer_.set("photons_per_pass", std::to_string(p.integer("photonsperiteration", 0)),
                          here, t.line);
        renderer_.set("initial_radius", std::to_string(p.real("radius", 1.f)), here, t.line);
        if (p.has("seed"))
            renderer_.set("seed", std::to_string(p.integer("seed", 0)), here, t.line);
    } else {
        // foton's own integrators by name, their parameters foton's renderer settings. The
        // scene layer does not know the integrator table: a name that is none of them fails
        // when the settings are read, at this file and line, with the list of names.
        renderer_.set("type", type, here, t.line);
        for (const Param& q : p.params) {
            q.used = true;
            if (q.numbers.size() + q.strings.size() != 1)
                p.fail(q, "foton's renderer settings take one value");
            renderer_.set(q.name, number_text(q), q.file, q.line);
        }
    }
    warn_unused(p, "Integrator \"" + type + "\"");
    count("Integrator " + type);
}

void Importer::pixel_filter(const Token& t, const std::string& type, const ParamList& p) {
    // pbrt-v4 calls its Lanczos filter "sinc".
    FilterType kind;
    if (!parse_filter_type(type == "sinc" ? "lanczos" : type, kind))
        fail(t, "unknown PixelFilter '" + type + "' (box, triangle, gaussian, mitchell, sinc)");
    // pbrt-v4's radius and shape for each type when the file gives none.
    const float fallback = default_filter_radius(kind);
    const float xr = p.real("xradius", fallback), yr = p.real("yradius", fallback);
    if (!(xr > 0.f && yr > 0.f && xr <= 16.f && yr <= 16.f))
        fail(t, "PixelFilter xradius and yradius must be in (0, 16] pixels");
    FilterShape shape;
    if (kind == FilterType::Gaussian) {
        shape.sigma = p.real("sigma", shape.sigma);
        if (!(shape.sigma > 0.f)) fail(t, "PixelFilter \"gaussian\": sigma must be positive");
    } else if (kind == FilterType::Mitchell) {
        shape.b = p.real("B", shape.b);
        shape.c = p.real("C", shape.c);
        if (!(shape.b >= 0.f && shape.b <= 1.f && shape.c >= 0.f && shape.c <= 1.f))
            fail(t, "PixelFilter \"mitchell\": B and C must be in [0, 1]");
    } else if (kind == FilterType::Lanczos) {
        shape.tau = p.real("tau", shape.tau);
        if (!(shape.tau > 0.f)) fail(t, "PixelFilter \"" + type + "\": tau must be positive");
    }
    pixel_filter_ = PixelFilter::make(kind, xr, yr, shape);
    warn_unused(p, "PixelFilter \"" + type + "\"");
    count("PixelFilter " + type);
}

void Importer::finish_camera() {
    scene_.film.filter = pixel_filter_;
    Camera& c = scene_.camera;
    const Affine world_from_camera = camera_from_world_.inverse();
    const Vec3 eye = world_from_camera.point({0, 0, 0});
    const Vec3 forward = normalize(world_from_camera.vector({0, 0, 1}));
    const Vec3 up = normalize(world_from_camera.vector({0, 1, 0}));
    const Vec3 right = world_from_camera.vector({1, 0, 0});
    c.type = camera_type_ == "perspective" ? CameraType::Perspective : CameraType::Orthographic;
    c.eye = eye;
    c.target = eye + forward;
    c.up = up;
    c.d = 1.f;
    // pbrt's screen window spans [-1, 1] on the image's shorter side, at the distance where
    // it covers the field of view (perspective) or in scene units (orthographic).
    const float scale = camera_type_ == "perspective" ? std::tan(0.5f * fov_ * kPi / 180.f) : 1.f;
    c.pixel_size = 2.f * scale / float(std::min(width_, height_));
    if (screen_window_) {
        const std::vector<float>& sw = *screen_window_;
        const float sx = (sw[1] - sw[0]) / float(width_), sy = (sw[3] - sw[2]) / float(height_);
        if (std::fabs(sw[0] + sw[1]) > 1e-4f * (sw[1] - sw[0]) ||
            std::fabs(sw[2] + sw[3]) > 1e-4f * (sw[3] - sw[2]) || std::fabs(sx - sy) > 1e-4f * sx)
            throw InputError(camera_file_, camera_line_,
                             "screenwindow must be centred with square pixels");
        c.pixel_size = sx * scale;
    }
    c.lens_radius = lens_radius_;
    c.focal_distance = focal_distance_;
    c.setup();
    // pbrt's camera space is left-handed; a transform may mirror it again.
    if (dot(c.u, right) < 0.f) {
        c.mirror = true;
        c.setup();
    }
    // set_resolution keeps the view plane's width: give it the width it is measured in.
    scene_.film.width = width_;
    scene_.film.pixel_size = c.pixel_size;
    scene_.set_resolution(width_, height_);
    if (crop_) scene_.set_crop((*crop_)[0], (*crop_)[1], (*crop_)[2], (*crop_)[3]);
}

}  // namespace foton::pbrt
