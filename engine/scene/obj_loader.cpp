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
    std::vector<float> pos, nrm;
    struct Corner {
        uint32_t v, n;
    };
    std::vector<Corner> corners;  // three per triangle
    bool all_have_normals = true;
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
        } else if (key == "f") {
            poly.clear();
            while (!c.at_end()) {
                const std::string_view tok = c.token();
                const std::size_t s1 = tok.find('/');
                Corner cr{0, UINT32_MAX};
                cr.v = resolve_index(tok.substr(0, s1), pos.size() / 3, "vertex", name, line);
                if (s1 != std::string_view::npos) {
                    const std::size_t s2 = tok.find('/', s1 + 1);
                    if (s2 != std::string_view::npos && s2 + 1 < tok.size())
                        cr.n =
                            resolve_index(tok.substr(s2 + 1), nrm.size() / 3, "normal", name, line);
                }
                if (cr.n == UINT32_MAX) all_have_normals = false;
                poly.push_back(cr);
            }
            if (poly.size() < 3)
                fail(name, line, "face with " + std::to_string(poly.size()) + " corners");
            for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
                corners.push_back(poly[0]);
                corners.push_back(poly[k]);
                corners.push_back(poly[k + 1]);
            }
        } else if (key == "vt" || key == "vp" || key == "o" || key == "g" || key == "s" ||
                   key == "usemtl" || key == "mtllib" || key == "l" || key == "p") {
            // Not used by the renderer.
        } else {
            fail(name, line, "unknown OBJ statement '" + std::string(key) + "'");
        }
    }
    if (corners.empty()) fail(name, 0, "no faces in OBJ file");

    ObjLoadResult res;
    TriangleMesh& m = res.mesh;
    res.has_normals = all_have_normals && !nrm.empty();
    if (res.has_normals) {
        // OBJ indexes positions and normals separately; weld each distinct pair once.
        std::unordered_map<uint64_t, uint32_t> weld;
        std::vector<uint32_t> remap;
        for (const Corner& cr : corners) {
            const uint64_t key = (uint64_t(cr.v) << 32) | cr.n;
            auto [it, inserted] = weld.try_emplace(key, uint32_t(m.positions.size() / 3));
            if (inserted) {
                for (int k = 0; k < 3; ++k) m.positions.push_back(pos[3 * cr.v + k]);
                for (int k = 0; k < 3; ++k) m.normals.push_back(nrm[3 * cr.n + k]);
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
    }
    if (kept.empty()) fail(name, 0, "every face of the OBJ file is degenerate");
    m.indices = std::move(kept);
    return res;
}

ObjLoadResult load_obj(const std::string& path) {
    return parse_obj(read_input_file(path, kMaxMeshFileBytes, "mesh file"), path);
}

}  // namespace foton
