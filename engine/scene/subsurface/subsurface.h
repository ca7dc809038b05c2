#pragma once
// A subsurface material's scattering (Material::subsurface indexes Scene::subsurfaces): the
// medium under the surface, by its coefficients in the scene's units of length, and the
// table of diffusion profiles for its phase asymmetry and boundary index. Materials of
// equal (g, eta) share one table.
#include <memory>

#include "bssrdf_table.h"
#include "engine/core/rgb.h"
#include "engine/scene/material.h"

namespace foton {

struct Subsurface {
    RGB sigma_a{0.f}, sigma_s{0.f};
    float eta = 1.33f;  // the boundary's index (inside over outside)
    std::shared_ptr<const BssrdfTable> table;
    // Given by a diffuse reflectance and mean free path: with a reflectance texture on the
    // material (Material::texture, its value the textured material's base_color), the
    // coefficients are made per entry point from it and `mfp`.
    bool from_reflectance = false;
    RGB mfp{1.f};
    // The coefficients at a point of material `m` (textured there).
    void coefficients(const Material& m, RGB& sa, RGB& ss) const;
};

// The coefficients of a medium (pbrt-v4's SubsurfaceFromDiffuse) whose multiple scattering
// under the table's boundary reflects `reflectance` of diffuse light (its effective albedo,
// per channel, clamped to [0, 1]) with mean free path `mfp` (1 / sigma_t).
void subsurface_from_reflectance(const BssrdfTable& table, const RGB& reflectance, const RGB& mfp,
                                 RGB& sigma_a, RGB& sigma_s);

}  // namespace foton
