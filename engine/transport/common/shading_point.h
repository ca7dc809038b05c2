#pragma once
// A vertex being shaded on a camera path: the surface, its material and shading frame, the
// direction back towards the camera, the throughput that reaches it, and which sample it
// serves. Shading steps take this one struct instead of a long list of arguments.
#include <cstdint>

#include "engine/core/rgb.h"
#include "engine/core/spectrum.h"
#include "engine/core/warp.h"
#include "engine/scene/material.h"
#include "surface.h"

namespace foton {

struct ShadingPoint {
    ShadingPoint(const SurfacePoint& sp_, const Material& m_, const Vec3& d, const RGB& weight_,
                 uint32_t slot_, uint32_t depth_, uint64_t key_)
        : sp(sp_),
          m(m_),
          frame(sp_.frame()),
          wo(frame.to_local(-d)),
          weight(weight_),
          slot(slot_),
          depth(depth_),
          key(key_) {}
    const SurfacePoint& sp;
    const Material& m;
    warp::Frame frame;  // around the shading normal
    Vec3 wo;            // towards the viewer, in `frame`
    RGB weight;         // the path's throughput up to here
    uint32_t slot;      // the sample whose radiance this adds to
    uint32_t depth;     // scattering vertices before this one
    uint64_t key;       // keys the sample's random numbers
    // A spectral path's wavelengths (core/spectrum.h; null: RGB): the lights' radiance is
    // read at them.
    const Wavelengths* wavelengths = nullptr;
};

}  // namespace foton
