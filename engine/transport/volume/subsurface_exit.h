#pragma once
// Where light that a path sent into a subsurface material comes out (pbrt-v4's volpath
// does the same): a probe segment drawn from the material's BSSRDF at the entry point
// (tabulated_bssrdf.h), traced through the scene hit after hit; of the hits on surfaces of
// the same material one is picked uniformly (reservoir sampling, so the hits need not be
// kept). The exit point's weight is Sp / (pdf_sp / hits): what the path's throughput is
// multiplied by before the BSSRDF's directional part (Lobe::subsurface_exit) scatters it on.
#include <cstdint>

#include "engine/accel/intersector.h"
#include "engine/core/stats.h"
#include "engine/transport/common/surface.h"

namespace foton {

struct SubsurfaceExitPoint {
    SurfacePoint sp;  // its normals face out of the material (the geometry's own side)
    uint32_t geom = 0;
    RGB weight;
};

// The exit for light entering at `entry` on geometry `geom` of material `m` (with a
// subsurface; textured at the entry), numbers u[0..2] choosing the probe and u[3] the hit; false
// when the probe finds no surface of the material (the path ends there, as in pbrt-v4).
bool find_subsurface_exit(const Scene& scene, const Intersector& accel, uint32_t geom,
                          const Material& m, const SurfacePoint& entry, const float u[4],
                          TraceCounters& counters, SubsurfaceExitPoint& out);

}  // namespace foton
