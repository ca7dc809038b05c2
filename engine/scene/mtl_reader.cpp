// MTL, the material files of OBJ: the statements a renderer of surfaces can honour, each
// checked with its line; the rest become notes.
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string_view>

#include "engine/core/error.h"
#include "mesh_file.h"

namespace foton {

namespace {

std::vector<std::string_view> split(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
        const std::size_t b = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
        if (i > b) out.push_back(line.substr(b, i - b));
    }
    return out;
}

std::string quoted(std::string_view s) {
    std::string out;
    out.reserve(s.size() + 2);
    out += '\'';
    out.append(s.data(), s.size());
    out += '\'';
    return out;
}

}  // namespace

std::map<std::string, FileMaterial> parse_mtl(const std::string& text, const std::string& name,
                                              const std::string& base_dir,
                                              std::vector<std::string>& notes) {
    std::map<std::string, FileMaterial> out;
    FileMaterial* cur = nullptr;
    int illum = 2;
    float dissolve = 1.f;
    int line = 0;
    auto note = [&](const std::string& what) {
        notes.push_back(name + ":" + std::to_string(line) + ": " + what);
    };
    auto number = [&](std::string_view tok) {
        float v = 0.f;
        const char* b = tok.data();
        if (!tok.empty() && *b == '+') ++b;
        auto [ptr, ec] = std::from_chars(b, tok.data() + tok.size(), v);
        if (tok.empty() || ec != std::errc() || ptr != tok.data() + tok.size() || !std::isfinite(v))
            throw InputError(name, line, "malformed number '" + std::string(tok) + "'");
        return v;
    };
    // Ends the material being read: illum and dissolve decide its kind.
    auto finish = [&] {
        if (!cur) return;
        if (illum == 3 || illum == 5) {
            cur->mirror = true;
        } else if (illum == 4 || illum == 6 || illum == 7 || illum == 9) {
            cur->glass = true;
        } else if (illum < 0 || illum > 10) {
            // Checked where it was read.
        } else if (illum == 0 || illum == 1) {
            cur->specular = RGB{0.f};  // no highlight in these models
        } else if (illum != 2) {
            notes.push_back(name + ": material '" + cur->name + "': illum " +
                            std::to_string(illum) + " rendered as illum 2");
        }
        if (!cur->bump_map.empty() && !cur->normal_map.empty())
            notes.push_back(name + ": material '" + cur->name +
                            "': norm is its normal map; map_Bump is read only if it is a height "
                            "map");
        // Dissolve is coverage: the share of light the surface stops (glass is transparent
        // by its own lobe).
        if (!cur->glass) {
            cur->alpha = dissolve;
        } else if (!cur->alpha_map.empty()) {
            cur->alpha_map.clear();
            notes.push_back(name + ": material '" + cur->name + "': map_d on glass ignored");
        }
    };
    const char* p = text.data();
    const char* end = p + text.size();
    while (p < end) {
        ++line;
        const char* eol = static_cast<const char*>(std::memchr(p, '\n', std::size_t(end - p)));
        if (!eol) eol = end;
        const std::vector<std::string_view> t = split({p, std::size_t(eol - p)});
        p = eol + 1;
        if (t.empty() || t[0][0] == '#') continue;
        const std::string_view key = t[0];
        if (key == "newmtl") {
            finish();
            if (t.size() < 2) throw InputError(name, line, "newmtl needs a name");
            const std::string n(t[1]);
            cur = &out[n];
            *cur = FileMaterial{};
            cur->name = n;
            illum = 2;
            dissolve = 1.f;
            continue;
        }
        if (!cur) throw InputError(name, line, "'" + std::string(key) + "' before any newmtl");
        auto color = [&]() {
            if (t.size() == 2) return RGB{number(t[1])};
            if (t.size() != 4)
                throw InputError(name, line, std::string(key) + " needs one or three numbers");
            const RGB c{number(t[1]), number(t[2]), number(t[3])};
            if (c.r < 0.f || c.g < 0.f || c.b < 0.f)
                throw InputError(name, line, std::string(key) + " must not be negative");
            return c;
        };
        auto one = [&]() {
            if (t.size() != 2) throw InputError(name, line, std::string(key) + " needs one number");
            return number(t[1]);
        };
        if (key == "Kd") {
            cur->diffuse = color();
            if (cur->diffuse.max_component() > 1.f)
                throw InputError(name, line, "Kd above 1 reflects more light than arrives");
        } else if (key == "Ks") {
            cur->specular = color();
            if (cur->specular.max_component() > 1.f)
                throw InputError(name, line, "Ks above 1 reflects more light than arrives");
        } else if (key == "Ke") {
            cur->emission = color();
            cur->emission_given = true;
        } else if (key == "Ns") {
            cur->exponent = one();
            if (cur->exponent < 0.f || cur->exponent > 1e6f)
                throw InputError(name, line, "Ns must be in [0, 1e6]");
        } else if (key == "Pm" || key == "Pr") {
            // The PBR extension's metallic and roughness: glTF's metallic-roughness model.
            const float v = one();
            if (!(v >= 0.f && v <= 1.f))
                throw InputError(name, line, std::string(key) + " must be in [0, 1]");
            (key == "Pm" ? cur->metallic : cur->roughness) = v;
        } else if (key == "Ni") {
            cur->ior = one();
            if (!(cur->ior > 0.f)) throw InputError(name, line, "Ni must be positive");
        } else if (key == "d" || key == "Tr") {
            const float v = one();
            if (!(v >= 0.f && v <= 1.f))
                throw InputError(name, line, std::string(key) + " must be in [0, 1]");
            dissolve = key == "d" ? v : 1.f - v;
        } else if (key == "illum") {
            const float v = one();
            if (v != std::floor(v) || v < 0.f || v > 10.f)
                throw InputError(name, line, "illum must be an integer in 0..10");
            illum = int(v);
        } else if (key == "map_Kd") {
            // Options -s and -o scale and offset the texture coordinates; the file name is
            // the rest of the line after them.
            std::size_t i = 1;
            while (i < t.size() && t[i][0] == '-') {
                const std::string_view opt = t[i];
                if ((opt == "-s" || opt == "-o") && i + 3 < t.size()) {
                    const float u = number(t[i + 1]), v = number(t[i + 2]);
                    (void)number(t[i + 3]);
                    if (opt == "-s") {
                        cur->diffuse_uv.su = u;
                        cur->diffuse_uv.sv = v;
                    } else {
                        cur->diffuse_uv.du = u;
                        cur->diffuse_uv.dv = v;
                    }
                    i += 4;
                } else {
                    throw InputError(name, line,
                                     "map_Kd option '" + std::string(opt) +
                                         "' is not supported (-s and -o are)");
                }
            }
            if (i >= t.size()) throw InputError(name, line, "map_Kd needs a file name");
            const char* b = t[i].data();
            std::string file(b, std::size_t(t.back().data() + t.back().size() - b));
            cur->diffuse_map = (std::filesystem::path(base_dir) / file).string();
        } else if (key == "Ka" || key == "Tf" || key == "sharpness") {
            note(quoted(key) + " ignored (no physical meaning in foton's models)");
        } else if (key == "map_Ke" || key == "norm" || key == "map_d") {
            // An emission map (radiance Ke times the map), the PBR extension's tangent-space
            // normal map or a dissolve map (cut-outs); options are not read.
            if (t.size() < 2) throw InputError(name, line, std::string(key) + " needs a file name");
            if (t[1].substr(0, 1) == "-")
                throw InputError(name, line, std::string(key) + " options are not supported");
            const char* b = t[1].data();
            const std::string file(b, std::size_t(t.back().data() + t.back().size() - b));
            (key == "norm"    ? cur->normal_map
             : key == "map_d" ? cur->alpha_map
                              : cur->emission_map) =
                (std::filesystem::path(base_dir) / file).string();
        } else if (key == "map_Bump" || key == "map_bump" || key == "bump") {
            // Option -bm scales a height map's values (the OBJ specification's multiplier).
            std::size_t i = 1;
            while (i < t.size() && t[i][0] == '-') {
                if (t[i] != "-bm" || i + 1 >= t.size())
                    throw InputError(name, line,
                                     std::string(key) + " option '" + std::string(t[i]) +
                                         "' is not supported (-bm is)");
                cur->bump_multiplier = number(t[i + 1]);
                i += 2;
            }
            if (i >= t.size())
                throw InputError(name, line, std::string(key) + " needs a file name");
            const char* b = t[i].data();
            const std::string file(b, std::size_t(t.back().data() + t.back().size() - b));
            cur->bump_map = (std::filesystem::path(base_dir) / file).string();
        } else if (key.substr(0, 4) == "map_" || key == "disp" || key == "decal" || key == "refl") {
            note(quoted(key) + " ignored: foton reads map_Kd, map_Ke, map_d, map_Bump and norm");
        } else {
            note("unknown MTL statement " + quoted(key) + " ignored");
        }
    }
    finish();
    return out;
}

}  // namespace foton
