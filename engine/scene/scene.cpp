#include "scene.h"

#include <utility>

#include "engine/core/error.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace foton {

const char* accel_name(AccelType a) {
    switch (a) {
        case AccelType::Brute:
            return "brute";
        case AccelType::BruteSimd:
            return "brute-simd";
        case AccelType::Grid:
            return "grid";
        case AccelType::Bvh:
            return "bvh";
        case AccelType::Embree:
            return "embree";
        case AccelType::Octree:
            return "octree";
        case AccelType::KdTree:
            return "kdtree";
    }
    return "?";
}

bool parse_accel(const std::string& s, AccelType& out) {
    if (s == "brute")
        out = AccelType::Brute;
    else if (s == "brute-simd")
        out = AccelType::BruteSimd;
    else if (s == "grid")
        out = AccelType::Grid;
    else if (s == "bvh")
        out = AccelType::Bvh;
    else if (s == "embree")
        out = AccelType::Embree;
    else if (s == "octree")
        out = AccelType::Octree;
    else if (s == "kdtree")
        out = AccelType::KdTree;
    else
        return false;
    return true;
}

const char* material_type_name(MaterialType t) {
    switch (t) {
        case MaterialType::Matte:
            return "matte";
        case MaterialType::Phong:
            return "phong";
        case MaterialType::Reflective:
            return "reflective";
        case MaterialType::Glass:
            return "glass";
        case MaterialType::Emitter:
            return "emitter";
        case MaterialType::Generic:
            return "generic";
    }
    return "?";
}

std::size_t Scene::num_triangles() const {
    std::size_t n = 0;
    for (const Object& o : objects)
        if (o.kind == ObjectKind::Mesh) n += meshes[o.index].num_triangles();
    return n;
}

std::size_t Scene::num_stored_triangles() const {
    std::size_t n = 0;
    for (const auto& m : meshes) n += m.num_triangles();
    return n;
}

Bounds3 Scene::object_bounds(uint32_t geom) const {
    const Object& o = objects[geom];
    if (o.kind == ObjectKind::Sphere) return spheres[o.index].bounds();
    if (o.kind == ObjectKind::Curves) return curves[o.index].bounds();
    if (o.kind == ObjectKind::Shape) return shapes[o.index].bounds();
    const Bounds3 b = meshes[o.index].bounds();
    const Instance* in = instance_of(geom);
    if (!in) return b;
    // The placed box's corners (tight for the box, not for the mesh).
    Bounds3 w;
    for (int c = 0; c < 8; ++c)
        w.extend(in->to_world.point(
            {(c & 1) ? b.hi.x : b.lo.x, (c & 2) ? b.hi.y : b.lo.y, (c & 4) ? b.hi.z : b.lo.z}));
    return w;
}

void Scene::world_corners(uint32_t geom, uint32_t tri, Vec3& p0, Vec3& p1, Vec3& p2) const {
    meshes[objects[geom].index].corners(tri, p0, p1, p2);
    if (const Instance* in = instance_of(geom)) {
        p0 = in->to_world.point(p0);
        p1 = in->to_world.point(p1);
        p2 = in->to_world.point(p2);
        if (in->to_world.determinant() < 0.f) std::swap(p1, p2);
    }
}

uint32_t Scene::add_instance(uint32_t mesh, const Affine& to_world, uint32_t material,
                             bool smooth) {
    Object o;
    o.kind = ObjectKind::Mesh;
    o.index = mesh;
    o.material = material;
    o.smooth = smooth && !meshes[mesh].normals.empty();
    o.instance = int32_t(instances.size());
    instances.push_back({to_world, to_world.inverse()});
    objects.push_back(o);
    return uint32_t(objects.size() - 1);
}

Bounds3 Scene::bounds() const {
    Bounds3 b;
    for (uint32_t g = 0; g < objects.size(); ++g) b.extend(object_bounds(g));
    return b;
}

void Scene::check_extent() const {
    const Bounds3 b = bounds();
    const float c[6] = {b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z};
    for (const float x : c)
        if (!(std::fabs(x) <= kMaxCoordinate)) {
            char buf[192];
            std::snprintf(buf, sizeof buf,
                          "the geometry reaches from (%g, %g, %g) to (%g, %g, %g): coordinates "
                          "must be finite and within +-%g",
                          double(b.lo.x), double(b.lo.y), double(b.lo.z), double(b.hi.x),
                          double(b.hi.y), double(b.hi.z), double(kMaxCoordinate));
            throw InputError(source, 0, buf);
        }
}

std::size_t Scene::memory_bytes() const {
    std::size_t n = spheres.size() * sizeof(Sphere) + objects.size() * sizeof(Object) +
                    materials.size() * sizeof(Material) + instances.size() * sizeof(Instance);
    for (const auto& m : meshes) n += m.memory_bytes();
    for (const auto& c : curves) n += c.memory_bytes();
    for (const auto& sh : shapes)
        n += sizeof(AnalyticShape) + sh.shapes().size() * sizeof(ShapePrimitive);
    if (environment)
        for (const EnvLayer& e : environment->layers())
            n += e.map.texels.size() * sizeof(RGB) * 2;  // + its density
    return n;
}

void check_image_size(int width, int height, const std::string& file, int line) {
    if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide ||
        uint64_t(width) * uint64_t(height) > kMaxImagePixels)
        throw InputError(file, line,
                         "image " + std::to_string(width) + "x" + std::to_string(height) +
                             " is outside the limits: sides 1.." + std::to_string(kMaxImageSide) +
                             ", at most " + std::to_string(kMaxImagePixels) + " pixels");
}

namespace {

// The object of kind `kind` at `index` of its vector (each adder pushes the geometry first).
uint32_t add_object(std::vector<Object>& objects, ObjectKind kind, std::size_t index,
                    uint32_t material) {
    Object o;
    o.kind = kind;
    o.index = uint32_t(index);
    o.material = material;
    objects.push_back(o);
    return uint32_t(objects.size() - 1);
}

}  // namespace

uint32_t Scene::add_mesh(TriangleMesh mesh, uint32_t material, bool smooth) {
    const bool has_normals = !mesh.normals.empty();
    meshes.push_back(std::move(mesh));
    const uint32_t id = add_object(objects, ObjectKind::Mesh, meshes.size() - 1, material);
    objects[id].smooth = smooth && has_normals;
    return id;
}

uint32_t Scene::add_curves(CurveSet set, uint32_t material) {
    curves.push_back(std::move(set));
    return add_object(objects, ObjectKind::Curves, curves.size() - 1, material);
}

uint32_t Scene::add_shape(AnalyticShape shape, uint32_t material) {
    shapes.push_back(std::move(shape));
    return add_object(objects, ObjectKind::Shape, shapes.size() - 1, material);
}

uint32_t Scene::add_sphere(const Sphere& sphere, uint32_t material) {
    spheres.push_back(sphere);
    return add_object(objects, ObjectKind::Sphere, spheres.size() - 1, material);
}

const Material& Scene::textured(const Material& m, const TexPoint& at,
                                std::optional<Material>& scratch) const {
    const Point2 uv = at.uv;
    Material& out = scratch.emplace(m);
    if (m.texture >= 0 || m.vertex_colored) {
        const RGB t = (m.texture >= 0 ? textures[std::size_t(m.texture)].eval(texture_images, at)
                                      : RGB{1.f}) *
                      at.vertex_color;
        out.base_color = m.base_color * t;
        out.bsdf = m.bsdf.with_texture(m.textured_lobes, t);
    }
    if (m.emission_texture >= 0)
        out.emission =
            m.emission * textures[std::size_t(m.emission_texture)].eval(texture_images, at);
    // pbrt-v4's hair: the fibre's offset across its width from v.
    for (int i = 0; i < m.bsdf.size(); ++i)
        if (m.bsdf.lobe(i).type == LobeType::Hair)
            out.bsdf.set_param(i, LobeParam::HairOffset, -1.f + 2.f * std::clamp(uv.y, 0.f, 1.f));
    for (int i = 0; i < m.num_float_params; ++i) {
        const Material::FloatParam& fp = m.float_params[std::size_t(i)];
        const Texture& tx = textures[std::size_t(fp.texture)];
        // One lookup: the float value, or the one channel a packed texture keeps it in.
        float v;
        if (fp.channel == 0) {
            v = tx.eval_float(texture_images, at);
        } else if (fp.channel == 4) {
            // An image's alpha (1 where it has none), scaled as a float texture.
            v = tx.kind == TextureKind::Image && !texture_images[tx.image].alpha.empty()
                    ? tx.eval_float(texture_images, at)
                    : tx.scale.r;
        } else {
            const RGB c = tx.eval(texture_images, at);
            v = fp.channel == 1 ? c.r : fp.channel == 2 ? c.g : c.b;
        }
        if (fp.target == LobeParam::Weight || fp.target == LobeParam::WeightComplement) {
            const float w = std::clamp(v, 0.f, 1.f);
            out.bsdf.set_param(fp.lobe, fp.target,
                               fp.target == LobeParam::WeightComplement ? fp.k * w : w);
            continue;
        }
        v = std::max(v, 0.f);
        const float alpha = fp.remap == Material::Remap::Sqrt     ? std::sqrt(v)
                            : fp.remap == Material::Remap::Square ? v * v
                                                                  : v;
        // The lobe stays rough where the texture falls below pbrt's specular limit (1e-3): a
        // lobe cannot change from glossy to delta between hits.
        out.bsdf.set_param(fp.lobe, fp.target, std::clamp(alpha, 1e-3f, 2.f));
    }
    return out;
}

void Scene::set_resolution(int width, int height) {
    // Keep the view plane's extent: the field of view does not change with resolution.
    const float view_w = film.pixel_size * float(film.width);
    const float view_h = film.pixel_size * float(film.height);
    film.width = film.full_width = width;
    film.height = film.full_height = height;
    film.x0 = film.y0 = 0;
    film.pixel_size = vertical_fov_fixed ? view_h / float(height) : view_w / float(width);
    camera.width = width;
    camera.height = height;
    camera.crop(0, 0, width, height);
    camera.pixel_size = film.pixel_size;
}

void Scene::set_crop(int x0, int x1, int y0, int y1) {
    film.x0 = x0;
    film.y0 = y0;
    film.width = x1 - x0;
    film.height = y1 - y0;
    camera.crop(x0, y0, x1 - x0, y1 - y0);
}

std::string Scene::summary() const {
    char buf[512];
    std::string s;
    std::snprintf(buf, sizeof buf, "scene      %s\n", source.c_str());
    s += buf;
    std::snprintf(buf, sizeof buf, "objects    %zu (%zu meshes, %zu spheres)\n", objects.size(),
                  meshes.size(), spheres.size());
    s += buf;
    std::snprintf(buf, sizeof buf, "triangles  %zu (%zu degenerate skipped)\n", num_triangles(),
                  skipped_degenerate);
    s += buf;
    if (!curves.empty()) {
        std::size_t segments = 0;
        for (const CurveSet& c : curves) segments += c.size();
        std::snprintf(buf, sizeof buf, "curves     %zu segments in %zu sets\n", segments,
                      curves.size());
        s += buf;
    }
    if (!shapes.empty()) {
        // "shapes     3: cylinder, torus, CSG of 3 solids"
        s += "shapes     " + std::to_string(shapes.size()) + ":";
        for (std::size_t i = 0; i < shapes.size(); ++i) {
            const AnalyticShape& sh = shapes[i];
            s += i ? ", " : " ";
            s += sh.csg() ? "CSG of " + std::to_string(sh.shapes().size()) + " solids"
                          : std::string(shape_type_name(sh.shapes()[0].type));
        }
        s += "\n";
    }
    if (!instances.empty()) {
        std::snprintf(buf, sizeof buf, "instances  %zu placements sharing %zu stored triangles\n",
                      instances.size(), num_stored_triangles());
        s += buf;
    }
    std::snprintf(buf, sizeof buf,
                  "lights     %zu (point %zu, directional %zu, spot %zu, area %zu), ambient %.3g\n",
                  lights.count(), lights.points.size(), lights.directionals.size(),
                  lights.spots.size(), lights.areas.size(), double(ambient.intensity));
    s += buf;
    if (environment)
        for (const EnvLayer& e : environment->layers()) {
            if (e.mapping == EnvMapping::Constant)
                std::snprintf(buf, sizeof buf, "environment constant (%g, %g, %g)\n",
                              double(e.scale.r), double(e.scale.g), double(e.scale.b));
            else
                std::snprintf(buf, sizeof buf, "environment %s %dx%d %s, scale (%g, %g, %g)\n",
                              env_mapping_name(e.mapping), e.map.width, e.map.height,
                              e.map.path.c_str(), double(e.scale.r), double(e.scale.g),
                              double(e.scale.b));
            s += buf;
        }
    std::size_t emitting = 0;
    for (const Object& o : objects) emitting += materials[o.material].emission.is_black() ? 0 : 1;
    if (emitting > 0) {
        std::snprintf(buf, sizeof buf, "emitters   %zu emitting objects\n", emitting);
        s += buf;
    }
    for (const Medium& m : media) {
        const char* tail = &m - media.data() == camera_medium ? ", the camera's" : "";
        if (m.kind == MediumKind::RGBGrid) {
            const DensityGrid& d = *m.density;
            std::snprintf(buf, sizeof buf,
                          "medium     %s (rgb grid %dx%dx%d): extinction up to %g, g %g%s%s\n",
                          m.name.c_str(), d.nx(), d.ny(), d.nz(),
                          double(d.max_value() * m.grid_scale), double(m.g),
                          m.emits() ? ", emits" : "", tail);
            s += buf;
            continue;
        }
        const RGB st = m.sigma_t();
        std::snprintf(buf, sizeof buf,
                      "medium     %s%s: sigma_t (%g, %g, %g), albedo (%g, %g, %g), g %g%s%s\n",
                      m.name.c_str(), m.density ? " (density grid)" : "", double(st.r),
                      double(st.g), double(st.b), double(st.r > 0.f ? m.sigma_s.r / st.r : 0.f),
                      double(st.g > 0.f ? m.sigma_s.g / st.g : 0.f),
                      double(st.b > 0.f ? m.sigma_s.b / st.b : 0.f), double(m.g),
                      m.emits() ? ", emits" : "", tail);
        s += buf;
    }
    const Bounds3 b = bounds();
    std::snprintf(buf, sizeof buf, "bounds     (%g, %g, %g) - (%g, %g, %g)\n", b.lo.x, b.lo.y,
                  b.lo.z, b.hi.x, b.hi.y, b.hi.z);
    s += buf;
    std::snprintf(buf, sizeof buf, "materials  %zu:", materials.size());
    s += buf;
    for (const Material& m : materials) {
        s += " " + (m.name.empty() ? std::string(material_type_name(m.type)) : m.name);
        if (!m.emission.is_black()) s += "(emits)";
    }
    s += "\n";
    std::snprintf(buf, sizeof buf, "memory     %.2f MiB (geometry)\n",
                  double(memory_bytes()) / (1024.0 * 1024.0));
    s += buf;
    // A perspective camera's field of view; an orthographic one's view height in scene units.
    const bool ortho = camera.type == CameraType::Orthographic;
    std::snprintf(buf, sizeof buf, "camera     %s, eye (%g, %g, %g), %s %.*f%s\n",
                  camera_type_name(camera.type), camera.eye.x, camera.eye.y, camera.eye.z,
                  ortho ? "view height" : "vertical fov", ortho ? 4 : 2,
                  ortho ? double(camera.pixel_size) * double(camera.height)
                  : camera.type == CameraType::Perspective ? camera.vertical_fov_degrees()
                                                           : 0.0,
                  ortho ? "" : " deg");
    s += buf;
    std::snprintf(buf, sizeof buf, "film       %d x %d, gamma %g, filter %s\n", film.width,
                  film.height, film.gamma, film.filter.describe().c_str());
    s += buf;
    if (!imported.empty()) {
        s += "imported  ";
        for (const std::string& i : imported) s += " " + i + ";";
        s.back() = '\n';
    }
    for (const std::string& w : warnings) s += "ignored    " + w + "\n";
    return s;
}

}  // namespace foton
