#pragma once
// A triangle mesh in world space (object transforms are applied at load time, so one OBJ
// placed several times becomes several meshes).
#include <cstdint>
#include <string>
#include <vector>

#include "engine/core/math.h"
#include "engine/core/rgb.h"
#include "engine/core/sampler.h"

namespace foton {

struct TriangleMesh {
    std::string name;
    std::vector<float> positions;  // xyz per vertex
    std::vector<float> normals;    // xyz per vertex, empty for flat shading
    std::vector<float> uvs;        // uv per vertex, empty when the mesh has none
    // A second uv set (glTF: the TEXCOORD_n some of its material's textures read besides the
    // first's), empty when none.
    std::vector<float> uvs2;
    // Linear RGB per vertex multiplying the base colour (glTF's COLOR_0), empty when none.
    std::vector<float> colors;
    std::vector<uint32_t> indices;  // three per triangle

    std::size_t num_triangles() const { return indices.size() / 3; }
    std::size_t num_vertices() const { return positions.size() / 3; }
    Vec3 vertex(uint32_t i) const {
        return {positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]};
    }
    Vec3 vertex_normal(uint32_t i) const {
        return {normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]};
    }
    void corners(uint32_t tri, Vec3& p0, Vec3& p1, Vec3& p2) const {
        p0 = vertex(indices[3 * tri]);
        p1 = vertex(indices[3 * tri + 1]);
        p2 = vertex(indices[3 * tri + 2]);
    }
    // The texture coordinates of triangle tri's corners in uv set `set` (0 or 1): its uv, or
    // pbrt's default parametrisation (0, 0), (1, 0), (1, 1) when the mesh has none; set 1
    // falls back to set 0.
    void corner_uvs(uint32_t tri, Point2& t0, Point2& t1, Point2& t2, int set = 0) const {
        const std::vector<float>& uvs = set == 1 && !uvs2.empty() ? uvs2 : this->uvs;
        if (uvs.empty()) {
            t0 = {0.f, 0.f}, t1 = {1.f, 0.f}, t2 = {1.f, 1.f};
            return;
        }
        const uint32_t* ix = &indices[3 * std::size_t(tri)];
        t0 = {uvs[2 * ix[0]], uvs[2 * ix[0] + 1]};
        t1 = {uvs[2 * ix[1]], uvs[2 * ix[1] + 1]};
        t2 = {uvs[2 * ix[2]], uvs[2 * ix[2] + 1]};
    }
    // The vertex colour at barycentrics (u, v) of triangle tri (white without colours).
    RGB color_at(uint32_t tri, float u, float v) const {
        if (colors.empty()) return RGB{1.f};
        const uint32_t* ix = &indices[3 * std::size_t(tri)];
        const float w = 1.f - u - v;
        auto c = [&](int k) {
            const float* q = &colors[3 * std::size_t(ix[k])];
            return RGB{q[0], q[1], q[2]};
        };
        return c(0) * w + c(1) * u + c(2) * v;
    }
    Bounds3 bounds() const;
    // Area-weighted vertex normals from the faces (for meshes given without normals).
    void compute_smooth_normals();
    void transform(const Affine& xf);
    std::size_t memory_bytes() const {
        return (positions.size() + normals.size() + uvs.size() + uvs2.size() + colors.size()) *
                   sizeof(float) +
               indices.size() * 4;
    }
};

struct Sphere {
    Vec3 center;
    float radius = 1.f;
    // Places the sphere under `xf`; false (unchanged) when xf does not scale uniformly.
    bool transform(const Affine& xf);
    Bounds3 bounds() const {
        Bounds3 b;
        b.extend(center - Vec3{radius, radius, radius});
        b.extend(center + Vec3{radius, radius, radius});
        return b;
    }
};

// Robust ray/sphere test (the quadratic solved in a cancellation-free form).
// Returns the nearest root in (tmin, tmax).
bool intersect_sphere(const Sphere& s, const Vec3& o, const Vec3& d, float tmin, float tmax,
                      float& t);

}  // namespace foton
