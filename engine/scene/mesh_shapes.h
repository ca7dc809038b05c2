#pragma once
// Triangle meshes made from other shape descriptions: Loop subdivision surfaces (pbrt-v4's
// `loopsubdiv`) and tessellated disks and cylinders (pbrt-v4's `disk` and `cylinder`), in
// their own object space. Errors (a non-manifold control mesh) throw std::invalid_argument
// without a location; the importer adds the Shape's line.
#include "mesh.h"

namespace foton {

// Loop's subdivision of a triangle control mesh, `levels` times (each splits every triangle
// into four: Loop's 1987 weights, beta = 3/16 at valence 3 and 3/(8n) above; boundary edges
// and vertices follow the cubic B-spline of the boundary), then every vertex moved to its
// limit position. Normals are the area-weighted face normals of the result (close to the
// limit surface's after a few levels). Winding is kept.
TriangleMesh loop_subdivide(const TriangleMesh& control, int levels);

// A disk (or annulus, inner_radius > 0) of `radius` in the plane z = height, facing +z, over
// phi in [0, phi_max] radians: `segments` around the full circle, its polygon's radius chosen
// so that its area is the disk's (an emitting disk keeps its power). uv as pbrt-v4's: u =
// phi / phi_max, v = (radius - r) / (radius - inner_radius).
TriangleMesh tessellate_disk(float height, float radius, float inner_radius, float phi_max,
                             int segments);

// A cylinder's side of `radius` about z from z_min to z_max over phi in [0, phi_max],
// outward normals (smooth: the cylinder's own), `segments` around the full circle with the
// polygon's radius chosen to keep the side's area; uv: u = phi / phi_max, v = (z - z_min) /
// (z_max - z_min).
TriangleMesh tessellate_cylinder(float radius, float z_min, float z_max, float phi_max,
                                 int segments);

}  // namespace foton
