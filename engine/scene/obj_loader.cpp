#include "obj_loader.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <unordered_map>
#include <vector>

#include "engine/core/error.h"
#include "engine/core/input_file.h"

namespace foton {

namespace {

struct Cursor {
    const char* p;
    const char* end;
    void skip_space() {
        while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
    }
    bool at_end() {
        skip_space();
        return p >= end;
    }
    std::string_view token() {
        skip_space();
        const char* b = p;
        while (p < end && *p != ' ' && *p != '\t' && *p != '\r') ++p;
        return {b, std::size_t(p - b)};
    }
};

[[noreturn]] void fail(const std::string& name, int line, const std::string& what) {
    throw InputError(name, line, what);
}

float parse_float(std::string_view tok, const std::string& name, int line) {
    if (tok.empty()) fail(name, line, "missing coordinate");
    float v = 0.f;
    const char* b = tok.data();
    if (*b == '+') ++b;
    auto [ptr, ec] = std::from_chars(b, tok.data() + tok.size(), v);
    if (ec != std::errc() || ptr != tok.data() + tok.size())
        fail(name, line, "malformed number '" + std::string(tok) + "'");
    if (!std::isfinite(v)) fail(name, line, "coordinate is NaN or infinite");
    return v;
}

// Resolves a 1-based (or negative, relative) OBJ index against `count` items so far.
uint32_t resolve_index(std::string_view tok, std::size_t count, const char* what,
                       const std::string& name, int line) {
    long long idx = 0;
    auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), idx);
    if (ec != std::errc() || ptr != tok.data() + tok.size())
        fail(name, line, std::string("malformed ") + what + " index '" + std::string(tok) + "'");
    const long long resolved = idx < 0 ? (long long)count + idx : idx - 1;
    if (idx == 0 || resolved < 0 || resolved >= (long long)count)
        fail(name, line,
             std::string(what) + " index " + std::to_string(idx) + " out of range (" +
                 std::to_string(count) + " defined so far)");
    return uint32_t(resolved);
}

}  // namespace

ObjLoadResult parse_obj(const std::string& text, const std::string& name) {
    ObjLoadResult res;
    std::vector<float> pos, nrm, tex;
    struct Corner {
        uint32_t v, t, n;
    };
    std::vector<Corner> corners;  // three per triangle
    std::vector<int32_t> tri_material;
    bool all_have_normals = true, all_have_uvs = true;
    int32_t material = -1;
    std::unordered_map<std::string, int32_t> material_index;
    std::vector<Corner> poly;

    int line = 0;
    const char* p = text.data();
    const char* end = p + text.size();
    while (p < end) {
        ++line;
        const char* eol = static_cast<const char*>(memchr(p, '\n', std::size_t(end - p)));
        if (!eol) eol = end;
        Cursor c{p, eol};
        p = eol + 1;
        const std::string_view key = c.token();
        if (key.empty() || key[0] == '#') continue;
        if (key == "v") {
            for (int k = 0; k < 3; ++k) pos.push_back(parse_float(c.token(), name, line));
            // An optional w or vertex colour may follow; ignore it.
        } else if (key == "vn") {
            for (int k = 0; k < 3; ++k) nrm.push_back(parse_float(c.token(), name, line));
        } else if (key == "vt") {
            // u and an optional v (and w, unused).
            tex.push_back(parse_float(c.token(), name, line));
            const std::string_view v = c.token();
            tex.push_back(v.empty() ? 0.f : parse_float(v, name, line));
        } else if (key == "f") {
            poly.clear();
            while (!c.at_end()) {
                const std::string_view tok = c.token();
                const std::size_t s1 = tok.find('/');
                Corner cr{0, UINT32_MAX, UINT32_MAX};
                cr.v = resolve_index(tok.substr(0, s1), pos.size() / 3, "vertex", name, line);
                if (s1 != std::string_view::npos) {
                    const std::size_t s2 = tok.find('/', s1 + 1);
                    const std::string_view t =
                        tok.substr(s1 + 1, s2 == std::string_view::npos ? std::string_view::npos
                                                                        : s2 - s1 - 1);
                    if (!t.empty())
                        cr.t = resolve_index(t, tex.size() / 2, "texture coordinate", name, line);
                    if (s2 != std::string_view::npos && s2 + 1 < tok.size())
                        cr.n =
                            resolve_index(tok.substr(s2 + 1), nrm.size() / 3, "normal", name, line);
                }
                if (cr.n == UINT32_MAX) all_have_normals = false;
                if (cr.t == UINT32_MAX) all_have_uvs = false;
                poly.push_back(cr);
            }
            if (poly.size() < 3)
                fail(name, line, "face with " + std::to_string(poly.size()) + " corners");
            for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
                corners.push_back(poly[0]);
                corners.push_back(poly[k]);
                corners.push_back(poly[k + 1]);
                tri_material.push_back(material);
            }
        } else if (key == "usemtl") {
            const std::string mtl(c.token());
            if (mtl.empty()) fail(name, line, "usemtl needs a material name");
            auto [it, inserted] =
                material_index.try_emplace(mtl, int32_t(res.material_names.size()));
            if (inserted) {
                res.material_names.push_back(mtl);
                res.material_lines.push_back(line);
            }
            material = it->second;
        } else if (key == "mtllib") {
            // File names may hold spaces: the rest of the line.
            c.skip_space();
            std::string lib(c.p, c.end);
            while (!lib.empty() && (lib.back() == ' ' || lib.back() == '\t' || lib.back() == '\r'))
                lib.pop_back();
            if (lib.empty()) fail(name, line, "mtllib needs a file name");
            res.libraries.push_back({lib, line});
        } else if (key == "vp" || key == "o" || key == "g" || key == "s" || key == "l" ||
                   key == "p") {
            // Groups, smoothing groups, lines and points do not change the surfaces.
        } else {
            fail(name, line, "unknown OBJ statement '" + std::string(key) + "'");
        }
    }
    if (corners.empty()) fail(name, 0, "no faces in OBJ file");

    TriangleMesh& m = res.mesh;
    res.has_normals = all_have_normals && !nrm.empty();
    const bool has_uvs = all_have_uvs && !tex.empty();
    // Without normals in the file, vertex normals are the faces' (as compute_smooth_normals
    // makes them) taken before uv seams split vertices: a seam must not show in the shading.
    bool face_normals = false;
    if (has_uvs && !res.has_normals) {
        TriangleMesh by_position;
        by_position.positions = pos;
        by_position.indices.reserve(corners.size());
        for (const Corner& cr : corners) by_position.indices.push_back(cr.v);
        by_position.compute_smooth_normals();
        nrm = std::move(by_position.normals);
        for (Corner& cr : corners) cr.n = cr.v;
        face_normals = true;
    }
    const bool weld_normals = res.has_normals || face_normals;
    if (weld_normals || has_uvs) {
        // OBJ indexes positions, uvs and normals separately; weld each distinct tuple once.
        struct Key {
            uint32_t v, t, n;
            bool operator==(const Key& o) const { return v == o.v && t == o.t && n == o.n; }
        };
        struct Hash {
            std::size_t operator()(const Key& k) const {
                return std::size_t(
                    ((uint64_t(k.v) * 0x9e3779b97f4a7c15ull) ^ k.t) * 0xbf58476d1ce4e5b9ull ^ k.n);
            }
        };
        std::unordered_map<Key, uint32_t, Hash> weld;
        std::vector<uint32_t> remap;
        remap.reserve(corners.size());
        for (const Corner& cr : corners) {
            const Key key{cr.v, has_uvs ? cr.t : 0, weld_normals ? cr.n : 0};
            auto [it, inserted] = weld.try_emplace(key, uint32_t(m.positions.size() / 3));
            if (inserted) {
                for (int k = 0; k < 3; ++k) m.positions.push_back(pos[3 * cr.v + k]);
                if (weld_normals)
                    for (int k = 0; k < 3; ++k) m.normals.push_back(nrm[3 * cr.n + k]);
                if (has_uvs)
                    for (int k = 0; k < 2; ++k) m.uvs.push_back(tex[2 * cr.t + k]);
            }
            remap.push_back(it->second);
        }
        m.indices = std::move(remap);
    } else {
        m.positions = std::move(pos);
        m.indices.reserve(corners.size());
        for (const Corner& cr : corners) m.indices.push_back(cr.v);
    }
    // Drop zero-area triangles (checked in double: collinear corners, repeated indices).
    std::vector<uint32_t> kept;
    kept.reserve(m.indices.size());
    for (std::size_t t = 0; t < m.indices.size() / 3; ++t) {
        const uint32_t* ix = &m.indices[3 * t];
        double a[3], b[3];
        for (int k = 0; k < 3; ++k) {
            a[k] = double(m.positions[3 * ix[1] + k]) - double(m.positions[3 * ix[0] + k]);
            b[k] = double(m.positions[3 * ix[2] + k]) - double(m.positions[3 * ix[0] + k]);
        }
        const double cx = a[1] * b[2] - a[2] * b[1], cy = a[2] * b[0] - a[0] * b[2],
                     cz = a[0] * b[1] - a[1] * b[0];
        if (cx * cx + cy * cy + cz * cz == 0.0) {
            ++res.degenerate_skipped;
            continue;
        }
        kept.insert(kept.end(), ix, ix + 3);
        res.triangle_material.push_back(tri_material[t]);
    }
    if (kept.empty()) fail(name, 0, "every face of the OBJ file is degenerate");
    m.indices = std::move(kept);
    return res;
}

ObjLoadResult load_obj(const std::string& path) {
    return parse_obj(read_input_file(path, kMaxMeshFileBytes, "mesh file"), path);
}

}  // namespace foton
