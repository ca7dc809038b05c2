#pragma once
// The XML scene loader's internals, shared by its parts: loader.cpp (the document, film,
// renderer, camera), lights.cpp, materials.cpp and objects.cpp. The helpers read attributes
// as checked numbers, colours and vectors and report every problem as `file:line: what`.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <initializer_list>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <pugixml.hpp>

#include "engine/core/error.h"
#include "engine/core/params.h"
#include "engine/scene/mesh_file.h"
#include "engine/scene/scene.h"
#include "engine/scene/xml_loader.h"

namespace foton::xml {

using Names = std::initializer_list<const char*>;

// The generic material types start with no diffuse part; the diffuse ones set it.
inline void generic(Material& m) {
    m.type = MaterialType::Generic;
    m.c_diffuse = 0.f;
    m.base_color = RGB{0.f};
}

inline bool in(const Names& names, const char* s) {
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
    void reject_duplicates(const pugi::xml_document& doc) const;
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
        const pugi::xml_attribute a = n.attribute(attr);
        if (!a) return fallback;
        uint64_t v = 0;
        if (parse_integer(a.value(), 1, 100000000, v) != IntegerText::Ok)
            fail(n,
                 std::string("attribute '") + attr + "' must be a positive integer (at most 1e8)");
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
    // An emitted quantity (a light's intensity or radiance, an emission) that the renderer can
    // sum without overflowing (light.h's kMaxEmission), or an error at n.
    RGB emitted(const pugi::xml_node& n, const RGB& v) const {
        if (const std::string why = emission_problem(v); !why.empty())
            fail(n, std::string("<") + n.name() + ">: the emitted colour x intensity " + why);
        return v;
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
    // media.cpp: <media>, and the medium an attribute names (kNoMedium when absent or "").
    void parse_media(const pugi::xml_node& n);
    int32_t medium_ref(const pugi::xml_node& n, const char* attr) const;
    MediumInterface medium_interface(const pugi::xml_node& object) const;
    std::shared_ptr<const DensityGrid> density_grid(const pugi::xml_node& e) const;
    std::shared_ptr<const DensityGrid> vdb_grid(const pugi::xml_node& e) const;
    std::vector<float> raw_floats(const pugi::xml_node& e, const char* attr,
                                  std::size_t count) const;
    std::size_t grid_counts(const pugi::xml_node& e, int n[3]) const;
    Bounds3 grid_box(const pugi::xml_node& e) const;
    void rgb_grid_medium(const pugi::xml_node& e, float scale, Medium& m) const;
    void vdb_temperature(const pugi::xml_node& e, Medium& m) const;
    std::map<std::string, int32_t> medium_ids_;
    void parse_objects(const pugi::xml_node& n);
    // shapes.cpp: analytic shapes and CSG trees.
    static bool is_shape_element(std::string_view k);
    ShapePrimitive shape_primitive(const pugi::xml_node& o, bool in_csg) const;
    void check_shape(const pugi::xml_node& o, bool in_csg, const Names& own_attrs,
                     const Names& own_children) const;
    float shape_phi_max(const pugi::xml_node& o) const;
    Affine axial_shape(const pugi::xml_node& o, bool in_csg, ShapePrimitive& s) const;
    uint32_t csg_node(const pugi::xml_node& o, const Affine& outer, AnalyticShape& shape,
                      int depth) const;
    void parse_shape_object(const pugi::xml_node& o);
    void parse_film(const pugi::xml_node& n);
    void parse_renderer(const pugi::xml_node& n);
    void parse_camera(const pugi::xml_node& n);
    uint32_t parse_material(const pugi::xml_node& object);
    static constexpr int kMaxMixDepth = 16;
    int mix_depth_ = 0;                       // of the mix being read
    std::map<std::string, uint32_t> images_;  // image file -> Scene::texture_images
    // A mesh file as read, the foton materials made of its materials, and (when instanced)
    // the Scene::meshes index of each part.
    struct LoadedMeshFile {
        MeshFile file;
        std::vector<int> materials;
        int grey = -1;
        std::vector<uint32_t> meshes;
    };
    std::map<std::string, LoadedMeshFile> mesh_files_;  // by path
    void place_mesh_file(const pugi::xml_node& o, const std::string& src, const std::string& path,
                         const Affine& xf, bool instanced);
    Material material(const pugi::xml_node& n, bool top);
    // <material type="..."> by type: each reader (material_types.cpp) checks its element and
    // adds the type's lobes; `top` is false inside a mix (which adds `weight`).
    struct MaterialReader {
        const char* type;
        void (Loader::*read)(const pugi::xml_node& n, bool top, Material& m);
    };
    static const std::vector<MaterialReader>& material_readers();
    // Fails on an attribute or child the type does not take (beyond type, weight inside a
    // mix, <emission> and <texture>, which every material takes).
    void check_material(const pugi::xml_node& n, bool top, Names attrs, Names children) const;
    void thesis_material(const pugi::xml_node& n, bool top, Material& m);
    void lambert_material(const pugi::xml_node& n, bool top, Material& m);
    void conductor_material(const pugi::xml_node& n, bool top, Material& m);
    void dielectric_material(const pugi::xml_node& n, bool top, Material& m);
    void diffuse_transmission_material(const pugi::xml_node& n, bool top, Material& m);
    void coated_material(const pugi::xml_node& n, bool top, Material& m);
    CoatLayer coat_layer(const pugi::xml_node& n) const;
    void interface_material(const pugi::xml_node& n, bool top, Material& m);
    void subsurface_material(const pugi::xml_node& n, bool top, Material& m);
    void microfacet_material(const pugi::xml_node& n, bool top, Material& m);
    void mix_material(const pugi::xml_node& n, bool top, Material& m);
    void material_texture(const pugi::xml_node& n, Material& m);
    void material_emission(const pugi::xml_node& n, Material& m) const;
    void material_normal_map(const pugi::xml_node& n, Material& m);
    void material_bump(const pugi::xml_node& n, Material& m);
    void material_roughness_map(const pugi::xml_node& n, Material& m);
    Fresnel conductor_fresnel(const pugi::xml_node& n) const;
    float roughness(const pugi::xml_node& n, const char* attr = "roughness") const;
    float exponent(const pugi::xml_node& n, const char* attr, float fallback) const;
    MicrofacetDistribution distribution(const pugi::xml_node& n, const char* fallback) const;
    Affine parse_transform(const pugi::xml_node& object) const;
    void add_area_light(const pugi::xml_node& n);
    void add_environment(const pugi::xml_node& n);
    // A <texture>-like element into Scene::textures; `amplitude`: it takes a `scale` that
    // multiplies its value (a bump's height, a roughness map's range).
    int32_t parse_texture(const pugi::xml_node& n, bool linear_default = false,
                          bool amplitude = false);

    const std::string& xml_;
    std::string name_, base_;
    std::vector<std::size_t> line_starts_;
    const RendererOverrides& overrides_;
    Scene scene_;
};

}  // namespace foton::xml
