#pragma once
// A camera subpath's medium vertex (subpath_media.h): where its flight scattered. Its joins,
// a light sample (s = 1) and the connections to the pixel's light path (s >= 2), are shadow
// rays through the media with their values and MIS weights; then the path goes on by the
// phase function. The phase function stands for the BSDF; there is no cosine, no Russian
// roulette and no merge at such a vertex.
#include <cstdint>

#include "camera_workspace.h"
#include "vcm_context.h"

namespace foton {

// The vertex's numbers: the light sample's (choice, position, triangle), the new direction's.
struct MediumVertexNumbers {
    float select;
    Point2 light;
    float triangle;
    Point2 direction;
};

// Path `slot` of ws scattered at p, its ray having come along d; `key` is the path's (ratio
// tracking's keys for its joins).
void scatter_in_medium(const VcmContext& c, const LightPathStore& store, CameraSubpathWorkspace& ws,
                       uint32_t slot, const Vec3& p, const Vec3& d, uint64_t key,
                       const MediumVertexNumbers& u);

}  // namespace foton
