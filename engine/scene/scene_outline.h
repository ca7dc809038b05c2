#pragma once
// A conservative outline of a scene's geometry in a few boxes, whatever its triangle count: the
// cells of an n^3 grid over the scene's bounds that some object's box (each triangle's, for
// meshes) overlaps, as voxels or greedily merged into larger boxes (the same union). The
// projection maps of environment, point and spot lights project it.
#include <vector>

#include "engine/core/math.h"

namespace foton {

struct Scene;

std::vector<Bounds3> scene_outline(const Scene& scene, int n, bool merged);

}  // namespace foton
