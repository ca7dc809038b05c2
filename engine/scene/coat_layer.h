#pragma once
// The parameters of a layered lobe (LobeType::Coated): a dielectric coat over a base, with an
// optional scattering medium of unit extinction between them (pbrt-v4's coateddiffuse and
// coatedconductor; the walk that evaluates them is coated.cpp's). The base is the lobe's own
// colour (a Lambertian base's reflectance, or a conductor's tint), Fresnel (the conductor's
// eta and k, already relative to the coat) and distribution (the conductor's roughness).
#include <cstdint>

#include "engine/core/rgb.h"
#include "microfacet.h"

namespace foton {

enum class CoatBase : uint8_t { Diffuse, Conductor };

struct CoatLayer {
    CoatBase base = CoatBase::Diffuse;
    bool coat_smooth = true;  // the coat is a specular interface (roughness alpha below 1e-3)
    bool base_smooth = true;  // a conductor base is a mirror
    uint8_t max_depth = 10;   // scattering events of one walk inside the layer
    uint8_t samples = 1;      // walks averaged per evaluation of f and pdf
    float ior = 1.5f;         // the coat's index (the outside is 1)
    float thickness = 0.01f;  // in mean free paths of the medium between the interfaces
    float g = 0.f;            // the medium's Henyey-Greenstein asymmetry
    RGB albedo{0.f};          // the medium's single-scattering albedo; black: no medium
    float weight = 1.f;       // a mix's weight on the whole stack (scaling the base would not
                              // scale the stack's reflectance: light crosses it many times)
    MicrofacetDistribution coat = MicrofacetDistribution::trowbridge_reitz(0.f, 0.f);
};

}  // namespace foton
