#pragma once
// What a camera path needs to be spectral (core/spectrum.h): its wavelengths, stratified over
// the pixel's samples, and the materials it meets read at them.
#include <algorithm>
#include <optional>

#include "camera_integrator.h"
#include "engine/core/rng.h"
#include "engine/core/spectrum.h"
#include "engine/scene/material.h"

namespace foton {

// The number a camera sample's wavelengths come from (stream `prefix`): the pixel's samples of
// a round take one stratum each of [0, 1), jittered, the strata shifted by a number of the
// pixel's, which evens out the colour noise of three wavelengths a path.
inline float wavelength_number(uint64_t prefix, const Scene& scene, const SampleJob& j) {
    const float jitter = rng::uniform_from(prefix, j.id, 0);
    if (j.pat_n <= 1) return jitter;
    const float shift = rng::uniform_from(prefix, pixel_pattern_key(scene, j), 1);
    const float u = (float(j.pat_i) + jitter) / float(j.pat_n) + shift;
    return std::min(u >= 1.f ? u - 1.f : u, 0x1.fffffep-1f);
}

// Material m as a path of wavelengths w sees it: its BSDF at them, in `scratch` (where
// Scene::material_at may have put a textured copy already). Its emission stays RGB, for the
// integrator to read as an illuminant.
inline const Material& material_at_wavelengths(const Material& m, const Wavelengths& w,
                                               std::optional<Material>& scratch) {
    if (m.is_interface || m.bsdf.empty()) return m;
    if (!scratch || &*scratch != &m) scratch = m;
    scratch->bsdf.to_wavelengths(w);
    return *scratch;
}

}  // namespace foton
