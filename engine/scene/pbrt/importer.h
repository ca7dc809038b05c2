#pragma once
// The pbrt-v4 scene importer's internals, shared by its parts: importer.cpp (files,
// tokens, directives, transforms, the attribute stack), options.cpp (camera, film, sampler,
// integrator), materials.cpp (materials and textures), lights.cpp and shapes.cpp (shapes,
// object instances). The result is an ordinary foton Scene: everything imported is
// counted for `foton info`, everything left out is a warning at its file and line, and
// everything that would make the image wrong is an InputError.
#include <array>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "engine/core/error.h"
#include "engine/scene/scene.h"
#include "engine/scene/xml_loader.h"
#include "param_list.h"
#include "tokenizer.h"

namespace foton::pbrt {

struct AreaLightDesc {
    RGB radiance{0.f};
    int32_t texture = -1;  // an image ("filename") multiplying radiance: into Scene::textures
    bool two_sided = false;
    int id = -1;  // -1: shapes do not emit
};

struct GraphicsState {
    Affine ctm;  // object to world (camera space before WorldBegin)
    bool reverse = false;
    uint32_t material = 0;  // into Importer::materials_
    AreaLightDesc area;
    // MediumInterface: the media's names ("" vacuum) and where it was given.
    std::string medium_inside, medium_outside, medium_file;
    int medium_line = 0;
};

struct TextureDesc {
    std::string type;  // "constant", "scale"
    RGB value{1.f};    // constant textures (and products of constants)
    bool is_float = false;
    int32_t scene_texture = -1;  // imagemap, checkerboard: into Scene::textures
};

class Importer {
  public:
    Importer(std::string path, std::string text, std::string base_dir,
             const RendererOverrides& overrides);
    Scene run();

  private:
    // importer.cpp
    Token next();
    Token expect_string(const Token& directive, const char* what);
    float expect_number(const Token& directive);
    ParamList read_params();
    // The wavelength-value pairs of spectrum file `rel` (named at t), checked.
    std::vector<double> spectrum_file_pairs(const Token& t, const std::string& rel);
    static constexpr uint64_t kMaxSpectrumFileBytes = 1 << 20;
    void directive(const Token& t);
    void include(const Token& t);
    // A file the scene names (`what` 'rel'), resolved against the main file's directory and
    // checked as a readable input file; an error at t otherwise.
    std::string input_path(const Token& t, const std::string& what, const std::string& rel,
                           uint64_t max_bytes);
    void apply(const Affine& xf, bool replace = false);
    [[noreturn]] void fail(const Token& t, const std::string& what) const {
        throw InputError(file(), t.line, what);
    }
    void warn(const std::string& where, int line, const std::string& what);
    void warn_unused(const ParamList& p, const std::string& what);
    void count(const std::string& what) { ++imported_[what]; }
    const std::string& file() const { return files_.back()->file(); }

    // options.cpp
    void camera(const Token& t, const std::string& type, const ParamList& p);
    void film(const Token& t, const std::string& type, const ParamList& p);
    void sampler(const Token& t, const std::string& type, const ParamList& p);
    void integrator(const Token& t, const std::string& type, const ParamList& p);
    void pixel_filter(const Token& t, const std::string& type, const ParamList& p);
    void finish_camera();

    // materials.cpp
    Material make_material(const Token& t, const std::string& type, const ParamList& p);
    // subsurface.cpp: pbrt-v4's subsurface material's medium into the scene, m.subsurface
    // and m.ior set (its boundary's lobe is make_material's).
    void subsurface_material(const Token& t, const ParamList& p, Material& m,
                             const std::string& what);
    uint32_t scene_material(const GraphicsState& gs);

    // textures.cpp
    void texture(const Token& t, const std::string& name, const std::string& kind,
                 const std::string& type, const ParamList& p);
    RGB reflectance(const ParamList& p, const std::string& name, RGB fallback,
                    const std::string& what);
    // The same, where a varying texture may stand: its Scene::textures index, or -1.
    RGB reflectance(const ParamList& p, const std::string& name, RGB fallback,
                    const std::string& what, int32_t& texture);
    // pbrt-v4's "mix" texture into `tex` (a constant when its operands are).
    void mix_texture(const Token& t, const ParamList& p, TextureDesc& tex);
    // pbrt-v4's fbm, wrinkled and windy float textures (Perlin noise at the point).
    void noise_texture(const Token& t, const std::string& type, const ParamList& p,
                       TextureDesc& tex);
    // pbrt-v4's "directionmix": tex1 where the normal is along dir, tex2 across it.
    void direction_mix_texture(const Token& t, const ParamList& p, TextureDesc& tex);
    // An imagemap's or checkerboard's mapping: uv (uscale, vscale, udelta, vdelta), or by
    // position (spherical, cylindrical, planar) through the current transform.
    void texture_mapping(const Token& t, const ParamList& p, Texture& st);
    // A texture into Scene::textures (its index); one made of textures (mix, product, ...)
    // nested more than 8 deep is an error at `t` (operands are copies: nesting multiplies).
    int32_t add_texture(const Token& t, Texture tx);
    // pbrt-v4's "scale" texture whose scale varies: a product texture into `tex`.
    void product_texture(const Token& t, const ParamList& p, TextureDesc& tex);
    // A mix's or product's operand `key`: a copy of the texture it names, or a constant
    // texture of its value (`varies` set when it is a varying texture).
    Texture texture_operand(const ParamList& p, const std::string& key, bool is_float,
                            float fallback, bool& varies);
    // The Scene::texture_images index of an imagemap's file, decoded once per file (its MIP
    // pyramid built for a MIP-mapped filter); its filter and anisotropy set on `st`.
    uint32_t image_texture(const Token& t, const ParamList& p, Texture& st);
    // An image file into Scene::texture_images (decoded once per file and encoding).
    uint32_t image_file(const Token& t, const std::string& rel, bool linear,
                        TextureWrap wrap = TextureWrap::Repeat);
    // The texture bound to parameter `name` ("texture reflectance" "t"), nullptr when the
    // parameter is not texture-valued; an error when no texture of that kind is defined.
    const TextureDesc* texture_ref(const ParamList& p, const std::string& name,
                                   bool is_float) const;
    std::map<std::string, uint32_t> images_;  // file -> Scene::texture_images
    // A float parameter or a constant float texture's value (a varying one: an error).
    float float_value(const ParamList& p, const std::string& name, float fallback);
    // The same, where a varying texture may stand: its Scene::textures index, or -1.
    float float_value(const ParamList& p, const std::string& name, float fallback,
                      int32_t& texture);

    // lights.cpp
    void light_source(const Token& t, const std::string& type, const ParamList& p);
    void infinite_light(const Token& t, const ParamList& p, float scale);
    void area_light(const Token& t, const std::string& type, const ParamList& p);

    // media.cpp
    void make_named_medium(const Token& t, const std::string& name, const ParamList& p);
    void medium_interface(const Token& t);
    int grid_samples(const Token& t, const std::string& what, const ParamList& p, int n[3]);
    Bounds3 grid_box(const Token& t, const std::string& what, const ParamList& p);
    std::shared_ptr<const DensityGrid> emission_scale_grid(const Token& t, const std::string& what,
                                                           const ParamList& p,
                                                           const DensityGrid& density);
    void rgb_grid_medium(const Token& t, const std::string& what, const ParamList& p, Medium& m);
    void uniform_temperature(const Token& t, const std::string& what, const ParamList& p,
                             Medium& m);
    void nanovdb_medium(const Token& t, const std::string& what, const ParamList& p, Medium& m);
    std::shared_ptr<const DensityGrid> uniform_grid(const Token& t, const std::string& what,
                                                    const ParamList& p);
    // A medium's index by name ("": vacuum), an error at where:line if there is none.
    int32_t medium_id(const std::string& name, const std::string& where, int line) const;
    // The current MediumInterface, for a shape.
    MediumInterface shape_media() const;
    std::map<std::string, int32_t> media_;  // name -> Scene::media
    std::string camera_medium_;             // the outside medium at Camera
    std::string camera_medium_file_;
    int camera_medium_line_ = 0;
    int integrator_line_ = 0;  // where an Integrator was given (0: pbrt's default)
    // The first dispersive glass (file, line, name): warned about unless the render is
    // spectral volpath, the one that disperses.
    std::string glass_file_, glass_name_;
    int glass_line_ = 0;

    // shapes.cpp
    void shape(const Token& t, const std::string& type, const ParamList& p);
    bool refracts(uint32_t material) const;  // the material has a transmission lobe
    ShapePrimitive disk_or_cylinder(const Token& t, const std::string& type, const ParamList& p);
    // Where shapes go: the scene, or the object definition being read.
    Scene& target() { return proto_ ? *proto_ : scene_; }
    void object_instance(const Token& t, const std::string& name);
    // curves.cpp
    void curve(const Token& t, const ParamList& p);
    // (scene material, curve form, medium) -> the curve set object holding such curves
    // The curve set of each (scene or object definition, material, form, medium).
    std::map<std::tuple<const Scene*, uint32_t, int, int32_t>, uint32_t> curve_objects_;

    std::vector<std::unique_ptr<Tokenizer>> files_;
    std::string base_;
    // Measured BRDFs read so far, by path (one file may serve many materials).
    std::map<std::string, std::shared_ptr<const MeasuredBrdf>> measured_files_;
    const RendererOverrides& overrides_;
    Scene scene_;
    ParamSet renderer_;

    GraphicsState gs_;
    std::vector<GraphicsState> stack_;
    std::vector<char> stack_kind_;  // 'a' AttributeBegin, 't' TransformBegin
    std::map<std::string, Affine> coordinate_systems_;
    bool in_world_ = false;
    bool transform_start_ = true;  // ActiveTransform: transforms change the start time

    std::vector<Material> materials_;
    std::map<std::string, uint32_t> named_materials_;
    std::map<std::string, TextureDesc> textures_;
    // (material, area light, alpha, alpha texture) -> Scene::materials
    std::map<std::tuple<uint32_t, int, float, int32_t>, uint32_t> scene_materials_;
    // The current shape's `alpha` (a float or a float texture), read by shape().
    float shape_alpha_ = 1.f;
    int32_t shape_alpha_texture_ = -1;
    int area_lights_ = 0;

    // The geometry of each ObjectBegin/ObjectEnd block, in world space at its definition
    // (with scene material indices): each ObjectInstance places a copy under its transform.
    std::map<std::string, Scene> prototypes_;
    // Per prototype, the Scene::meshes index of each of its meshes once instanced (shared).
    std::map<std::string, std::vector<uint32_t>> instance_meshes_;
    std::string defining_;  // the ObjectBegin block being read ("" outside)
    Scene* proto_ = nullptr;

    // The camera, read when it appears and placed once the film's resolution is known.
    Affine camera_from_world_;
    std::string camera_type_ = "perspective";
    float fov_ = 90.f, lens_radius_ = 0.f, focal_distance_ = 1e6f;
    // pbrt-v4's sensor imaging ratio, exposure time (the camera's shutter interval) x ISO /
    // 100: it scales the film, so every emitter is scaled by it (transport is linear).
    float exposure_time_ = 1.f, iso_ = 100.f;
    float imaging_ratio() const { return exposure_time_ * iso_ / 100.f; }
    std::optional<std::vector<float>> screen_window_;
    int camera_line_ = 0;
    std::string camera_file_;
    int width_ = 1280, height_ = 720;
    std::optional<std::array<int, 4>> crop_;  // x0 x1 y0 y1
    // The film's reconstruction filter: pbrt-v4's default Gaussian unless PixelFilter says.
    PixelFilter pixel_filter_ = PixelFilter::gaussian(1.5f, 1.5f, 0.5f);

    std::vector<std::string> warnings_;
    std::map<std::string, int> imported_;
};

constexpr int kMaxIncludeDepth = 32;

}  // namespace foton::pbrt
