#pragma once
// The pbrt-v4 scene the normal- and bump-map tests share: a floor z = 0 over [-50, 50]^2 with
// u along +x and v along +y, seen from above (8 x 8, one bounce), under a distant light of
// irradiance 1 arriving along -l; its Lambert of 0.5 takes `material_params` (a normal map,
// a displacement) after `textures` (Texture lines) are defined.
#include <string>

#include "engine/core/math.h"

namespace foton::test {

inline std::string lit_floor_scene(const std::string& textures, const std::string& material_params,
                                   const Vec3& l) {
    return "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [30]\n"
           "Film \"rgb\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"
           "Sampler \"independent\" \"integer pixelsamples\" [1]\n"
           "Integrator \"path\" \"integer maxdepth\" [1]\nWorldBegin\n"
           "LightSource \"distant\" \"point3 from\" [" +
           std::to_string(l.x) + " " + std::to_string(l.y) + " " + std::to_string(l.z) +
           "] \"point3 to\" [0 0 0] \"rgb L\" [1 1 1]\n" + textures +
           "Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5] " + material_params +
           "\nShape \"trianglemesh\" \"point3 P\" [-50 -50 0  50 -50 0  50 50 0  -50 50 0]\n"
           "  \"point2 uv\" [0 0  1 0  1 1  0 1] \"integer indices\" [0 1 2  0 2 3]\n";
}

}  // namespace foton::test
