#pragma once
// The scene model: everything the XML file describes, in world space, ready for the
// accelerators and integrators.
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "camera.h"
#include "curves.h"
#include "engine/core/math.h"
#include "engine/core/params.h"
#include "engine/core/rgb.h"
#include "engine/core/sampler.h"
#include "engine/film/pixel_filter.h"
#include "environment.h"
#include "light.h"
#include "material.h"
#include "measured_brdf.h"
#include "medium.h"
#include "mesh.h"
#include "shapes/csg_shape.h"
#include "subsurface/subsurface.h"
#include "texture.h"

namespace foton {

// brute: the thesis' brute force, every ray against every primitive with the scalar
// Möller–Trumbore; brute-simd: the same with the SIMD kernel (W triangles per test); grid: the
// thesis' nested uniform grids; bvh: our wide BVH (the default); embree: Intel Embree 3;
// octree, kdtree: per-mesh triangle octrees or SAH kd-trees under an object BVH (the thesis'
// chapter 8).
enum class AccelType { Brute, BruteSimd, Grid, Bvh, Embree, Octree, KdTree };
const char* accel_name(AccelType a);
bool parse_accel(const std::string& s, AccelType& out);

enum class ObjectKind { Mesh, Sphere, Curves, Shape };
// Meshes and spheres are traced by each backend; curves and analytic shapes by the wrappers
// above every backend (accel/curve_intersector.h, accel/shape_intersector.h), which the
// backends leave them to.
inline bool traced_by_backend(ObjectKind k) {
    return k == ObjectKind::Mesh || k == ObjectKind::Sphere;
}

// One geometry of the scene: its index is the geometry id reported in hits.
struct Object {
    ObjectKind kind = ObjectKind::Mesh;
    uint32_t index = 0;     // into Scene::meshes, spheres, curves or shapes
    uint32_t material = 0;  // into Scene::materials
    bool smooth = false;    // interpolate vertex normals (meshes)
    // A mesh placed by a transform (into Scene::instances), -1: none. The mesh is then kept
    // in its own space and shared by every object that places it: the accelerators build
    // one structure for it (a BLAS) and trace rays taken into that space.
    int32_t instance = -1;
    // The media on its two sides (medium.h): a boundary when they differ.
    MediumInterface media;
};

// The transform of an instanced object, both ways.
struct Instance {
    Affine to_world, to_object;
};

// The largest image a render makes: a side, and the pixel count (the accumulators hold about
// 40 bytes a pixel). Larger requests are bad input, not an allocation failure.
constexpr int kMaxImageSide = 32768;
constexpr uint64_t kMaxImagePixels = uint64_t(1) << 27;
// Throws InputError at file:line for an image beyond those limits.
void check_image_size(int width, int height, const std::string& file, int line);
// No coordinate of the scene's geometry may be NaN, infinite or beyond this: squared lengths
// and the bounds' diagonal must stay finite in float (a translation of 1e39, or two of 3e38,
// rendered black with exit 0).
inline constexpr float kMaxCoordinate = 1e18f;

struct FilmSettings {
    int width = 512, height = 512;  // the pixels rendered (a crop window's, when cropped)
    float pixel_size = 0.001f;
    float gamma = 2.2f;
    // pbrt-v4's maxcomponentvalue: each camera sample and each light-path splat is scaled down
    // so that its largest channel is at most this (fireflies tamed at the cost of bias).
    float max_sample_value = std::numeric_limits<float>::infinity();
    // A crop window: the rendered pixels are [x0, x0 + width) x [y0, y0 + height) of an image
    // of full_width x full_height (equal to width x height without a crop).
    int x0 = 0, y0 = 0;
    int full_width = 512, full_height = 512;
    // How the pixels reconstruct the image (the 1-pixel box unless the scene asks).
    PixelFilter filter;

    bool cropped() const { return width != full_width || height != full_height; }
    // Calls add(film pixel index, weight) for each film pixel a splat at image position
    // (fx, fy) reaches through the filter.
    template <class Add>
    void spread(float fx, float fy, Add&& add) const {
        filter.spread(fx, fy, x0, y0, width, height, add);
    }
    // The pixel's index in the full image: random streams are keyed by it, so a crop renders
    // exactly the pixels of the full image.
    uint64_t pixel_id(uint32_t x, uint32_t y) const {
        return (uint64_t(y) + uint64_t(y0)) * uint64_t(full_width) + uint64_t(x) + uint64_t(x0);
    }
    uint64_t full_pixels() const { return uint64_t(full_width) * uint64_t(full_height); }
};

struct Scene {
    std::string source;  // the XML file
    // What a ray that leaves the scene sees: the environment when there is one (an emitter,
    // sampled like the other lights), else the thesis' background colour (a backdrop: no
    // light is sampled from it and no photon or light path starts on it).
    RGB background{0.f};
    std::optional<Environment> environment;
    // The first camera of a placed model file (glTF), placed as the file: an XML scene renders
    // through its own <camera>; a model rendered directly through this one (model_scene.h).
    std::optional<ModelView> model_view;
    Ambient ambient;
    Lights lights;
    std::vector<Material> materials;
    std::vector<TriangleMesh> meshes;
    std::vector<Sphere> spheres;
    std::vector<CurveSet> curves;
    std::vector<AnalyticShape> shapes;  // disks, cylinders, cones, tori, boxes and CSG trees
    std::vector<Object> objects;
    std::vector<Instance> instances;
    std::vector<Texture> textures;
    std::vector<TextureImage> texture_images;  // decoded once, shared by textures
    // Some texture is MIP-mapped (Texture::trilinear): hits then work out their footprint.
    bool mip_mapped = false;
    // The media under subsurface materials' surfaces (Material::subsurface), and where the
    // scene first asks for one: integrators that do not follow light under surfaces refuse
    // such a scene at that file and line.
    std::vector<Subsurface> subsurfaces;
    // The measured BRDFs the materials' Measured lobes point to (measured_brdf.h).
    std::vector<std::shared_ptr<const MeasuredBrdf>> measured_brdfs;
    std::string subsurface_file;
    int subsurface_line = 0;
    // The diffusion profiles of asymmetry g under a boundary of index eta, computed once and
    // shared between the subsurface media of equal (g, eta).
    std::shared_ptr<const BssrdfTable> subsurface_table(float g, float eta);
    // A subsurface medium (its table from subsurface_table) made at file:line; its index.
    uint32_t add_subsurface(const Subsurface& s, const std::string& file, int line);
    // Participating media (medium.h), and the one the camera sits in.
    std::vector<Medium> media;
    int32_t camera_medium = kNoMedium;
    // Where the scene first asks for volumetric transport (a medium, or an interface material
    // that only bounds one); no file when it does not. Integrators that do not trace media
    // refuse such a scene at that file and line.
    std::string volumetric_file;
    int volumetric_line = 0;
    bool volumetric() const { return !volumetric_file.empty(); }
    void mark_volumetric(const std::string& file, int line) {
        if (volumetric_file.empty()) {
            volumetric_file = file;
            volumetric_line = line;
        }
    }
    AccelType accel = AccelType::Bvh;
    float grid_density = 0.5f;  // cells per triangle of the mesh grids
    // grid: build each mesh's grid when a ray first reaches the mesh, not before the render
    // (the ray-tracing thesis' lazy nested grid, 8.1.1).
    bool grid_lazy = false;
    Camera camera;
    FilmSettings film;
    // The renderer's settings as written (<renderer>, with --set applied), each with its file
    // and line: the integrators read and check them (transport/run/render_settings.h).
    ParamSet renderer;
    std::size_t skipped_degenerate = 0;
    // Imported formats (pbrt-v4): what was read ("Shape sphere x2"), and what was left out
    // or approximated, as "file:line: what" (shown by `foton info` and before a render).
    std::vector<std::string> imported;
    std::vector<std::string> warnings;

    // Adds a geometry with its material; returns its geometry id. A mesh is smooth-shaded
    // when `smooth` and it has vertex normals.
    uint32_t add_mesh(TriangleMesh mesh, uint32_t material, bool smooth);
    uint32_t add_sphere(const Sphere& sphere, uint32_t material);
    uint32_t add_curves(CurveSet curves, uint32_t material);
    bool has_curves() const { return !curves.empty(); }
    uint32_t add_shape(AnalyticShape shape, uint32_t material);
    // Places mesh `mesh` (kept in its own space, shared) by `to_world` (not singular), with
    // its material; returns the geometry id.
    uint32_t add_instance(uint32_t mesh, const Affine& to_world, uint32_t material, bool smooth);
    // Corners of triangle `tri` of mesh geometry `geom` in world space, wound so that their
    // cross product is the outward normal (a mirroring placement swaps two, as
    // TriangleMesh::transform does).
    void world_corners(uint32_t geom, uint32_t tri, Vec3& p0, Vec3& p1, Vec3& p2) const;
    // The instance transform of geometry `geom`, or null for geometry in world space.
    const Instance* instance_of(uint32_t geom) const {
        const int32_t i = objects[geom].instance;
        return i < 0 ? nullptr : &instances[std::size_t(i)];
    }

    // The material of geometry `geom` (a hit's geom id).
    const Material& material_of(uint32_t geom) const { return materials[objects[geom].material]; }
    // Material `m` at a surface point of uv coordinates `uv`: m itself, or, when it is
    // textured, a copy in `scratch` with the texture's value applied. (An optional:
    // untextured hits, the common case, construct nothing.)
    const Material& material_at(const Material& m, const TexPoint& at,
                                std::optional<Material>& scratch) const {
        return m.varies() ? textured(m, at, scratch) : m;
    }
    // The same for the material of geometry `geom`.
    const Material& material_at(uint32_t geom, const TexPoint& at,
                                std::optional<Material>& scratch) const {
        return material_at(material_of(geom), at, scratch);
    }
    // Radiance along a ray from o of direction d that leaves the scene.
    RGB background_along(const Vec3& o, const Vec3& d) const {
        return environment ? environment->Le(o, d) : background;
    }
    const Material& textured(const Material& m, const TexPoint& at,
                             std::optional<Material>& scratch) const;
    std::size_t num_triangles() const;         // as rendered: an instanced mesh per placement
    std::size_t num_stored_triangles() const;  // as stored: an instanced mesh once
    Bounds3 bounds() const;
    // Fails (InputError at `source`) when the bounds are not finite or reach beyond
    // kMaxCoordinate; every loader calls it on the scene it made.
    void check_extent() const;
    Bounds3 object_bounds(uint32_t geom) const;
    std::size_t memory_bytes() const;
    std::string summary() const;  // foton info (the scene; the renderer's line is the app's)
    // Applies film/camera consistency after width/height changes: the view plane keeps its
    // width (its height when vertical_fov_fixed), so the field of view does not change.
    void set_resolution(int width, int height);
    // The camera's vertical field of view is the given one (a glTF camera's yfov).
    bool vertical_fov_fixed = false;
    // Renders only pixels [x0, x1) x [y0, y1) of the image (after set_resolution).
    void set_crop(int x0, int x1, int y0, int y1);
};

}  // namespace foton
