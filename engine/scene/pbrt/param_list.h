#pragma once
// The parameter list of a pbrt-v4 directive ("float radius" [ 1 ] "rgb L" [ 15 15 15 ] ...),
// with typed getters. Every getter marks its parameter as read; what no getter read is
// reported by the importer as an unsupported parameter at its own line, never dropped in
// silence. Values are checked (finite, the right count) where they are read.
#include <optional>
#include <string>
#include <vector>

#include "engine/core/math.h"
#include "engine/core/rgb.h"

namespace foton::pbrt {

struct Param {
    std::string type, name;  // "float", "radius"
    std::vector<double> numbers;
    std::vector<std::string> strings;  // also "true"/"false" of bools
    std::string file;
    int line = 0;
    mutable bool used = false;
};

class ParamList {
  public:
    std::vector<Param> params;
    std::string file;  // where the directive is

    const Param* find(const std::string& name) const;
    bool has(const std::string& name) const { return find(name) != nullptr; }
    [[noreturn]] void fail(const Param& p, const std::string& what) const;

    float real(const std::string& name, float fallback) const;
    int integer(const std::string& name, int fallback) const;
    bool boolean(const std::string& name, bool fallback) const;
    std::string text(const std::string& name, const std::string& fallback) const;
    std::vector<float> reals(const std::string& name) const;
    std::vector<int> integers(const std::string& name) const;
    // point3 / vector3 / normal3 (and pbrt-v3's point, vector, normal) triples.
    std::vector<Vec3> triples(const std::string& name) const;
    std::vector<float> pairs(const std::string& name) const;  // point2 / vector2, flattened
    // A colour given as rgb, spectrum (named or wavelength-value pairs) or blackbody; nullopt
    // when absent. `illuminant`: emission spectra are normalised to luminance 1 as pbrt-v4
    // does (rgb values are taken as they are).
    std::optional<RGB> color(const std::string& name, bool illuminant) const;
    // An array of rgb values (pbrt-v4's rgbgrid), each component non-negative; empty if absent.
    std::vector<RGB> colors(const std::string& name) const;
    // The name of a texture bound to `name` ("texture reflectance" "checks"), or "".
    std::string texture(const std::string& name) const;

    // Parameters no getter has read, as "file:line: unsupported parameter 'float foo' of
    // <what>" lines.
    std::vector<std::string> unused(const std::string& what) const;
};

}  // namespace foton::pbrt
