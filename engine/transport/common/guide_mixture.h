#pragma once
// The BSDF strategy of a guided path vertex (path/path_guide.h): with probability alpha a
// direction from a guide's density over the sphere, else from the BSDF. Whatever weighs a
// direction against that strategy (the path's own weight, MIS against light sampling) must use
// the mixture's density, which this gives; without a guide it is the BSDF's own.
#include "engine/core/sphere_histogram.h"

namespace foton {

struct GuideMixture {
    const SphereHistogram* guide = nullptr;  // null: the vertex is not guided
    float alpha = 0.f;                       // probability of sampling the guide

    bool active() const { return guide != nullptr; }
    // The strategy's density of world direction wi, given the BSDF's density of it.
    float pdf(float bsdf_pdf, const Vec3& wi_world) const {
        if (!guide) return bsdf_pdf;
        return (1.f - alpha) * bsdf_pdf + alpha * guide->pdf(wi_world);
    }
};

}  // namespace foton
