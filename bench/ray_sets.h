#pragma once
// The benchmark scenes and ray sets of the kernel suite, shared by bench/ and the tests so
// that the tests check the very rays the benchmarks time. Everything is deterministic.
//   scenes:  bunny, dragon, teapot (../shared/meshes), cornell (the classic room with its two
//            blocks, as triangles), stadium (the teapot inside a huge sparse bowl);
//   primary: a width x width pinhole camera, rays in Morton (Z) order, so that any aligned
//            run of 4^j rays is a 2^j x 2^j pixel square (16 = 4x4, 64 = 8x8) and a run of
//            8 a 4x2 rectangle: packets and streams are coherent by construction;
//   diffuse: cosine-distributed directions from random surface points (incoherent);
//   shadow:  from the same surface points to a point light, tmax = the light's distance.
#include <string>
#include <vector>

#include "engine/scene/mesh.h"
#include "kernels/ray1.h"

namespace foton::bench {

struct KernelScene {
    std::string name;
    TriangleMesh mesh;
    Vec3 eye, target;
    float fov_deg = 45.f;
    Vec3 light;
};

struct RaySets {
    int width = 0;
    std::vector<kern::Ray1> primary, diffuse, shadow;
};

// One of "bunny", "dragon", "teapot", "cornell", "stadium". Throws on an unknown name.
KernelScene load_kernel_scene(const std::string& name);
RaySets make_ray_sets(const KernelScene& scene, int width, std::size_t surface_rays,
                      uint32_t seed = 5);

}  // namespace foton::bench
