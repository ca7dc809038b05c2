#pragma once
// What every family's settings parse reads (a floor below the families' own settings files,
// docs/architecture.md): the capability bits an integrator's row declares, the integrator as
// the settings' rules see it, the MIS heuristic's names, and the lighting split.
#include <cstdint>
#include <functional>
#include <string>

#include "engine/core/params.h"
#include "engine/film/aov.h"

namespace foton {

// What an integrator takes beyond the settings every family reads: the capability bits of its
// row in the integrator table (registry/integrators.h). The rules of the settings ask for
// these, not for integrator names, so a new integrator states what it supports in its row
// alone.
enum Capability : uint32_t {
    kCapCamera = 1u << 0,           // paths start at the camera, pixel by pixel: adaptive sampling
    kCapIrradianceCache = 1u << 1,  // indirect="irradiance_cache"
    kCapLightingSplit = 1u << 2,    // lighting=direct|indirect
    kCapPhotonGuide = 1u << 3,      // guided=true: photon-guided directions
    kCapBidirectional = 1u << 4,    // MIS over bidirectional strategies: balance or power, no
                                    // rr_depth (the subpaths' vertex rules must agree)
    kCapMerging = 1u << 5,          // merges light vertices: merge_index
    kCapStrategyDebug = 1u << 6,    // strategy="s,t"
    kCapPhotonMap = 1u << 7,        // has a photon map: cache_secondary="photon"
    kCapLightSelection = 1u << 8,   // light_selection: next event estimation's light choice
    kCapComponents = 1u << 9,       // the components AOV: its estimate's parts apart
    kCapMedia = 1u << 10,           // traces participating media (scenes with <media>)
    kCapSubsurface = 1u << 11,      // follows light under subsurface materials (BSSRDF)
    kCapRegularize = 1u << 12,      // regularize=true: BSDFs roughened after a diffuse bounce
};

// The AOVs (film/aov.h's bits) only integrators with a capability make: asked for by name
// elsewhere they are an error, `all` leaves them out.
struct AovRequirement {
    uint32_t aov, cap;
    const char* needs;  // "the variance AOV needs pixel samples:"
};
inline constexpr AovRequirement kAovRequirements[] = {
    {kAovVariance, kCapCamera, "the variance AOV needs pixel samples:"},
    {kAovComponents, kCapComponents, "the components AOV needs"},
};

// The chosen integrator as the settings' rules see it.
struct IntegratorTraits {
    std::string name;
    uint32_t caps = 0;
    // `type="a"`, `type="a" or "b"`, ...: the integrators with every bit of a capability, for
    // error messages.
    std::function<std::string(uint32_t)> names_with;
    bool has(uint32_t cap) const { return (caps & cap) == cap; }
    // Fails at `key`'s file and line unless the integrator has `cap`: "<what> needs ...".
    void require(const ParamSet& p, const char* key, uint32_t cap, const std::string& what) const {
        if (!has(cap)) p.fail(key, what + " needs " + names_with(cap));
    }
};

// How next event estimation and BSDF sampling are combined (common/mis.h weighs them).
// Mean: the photon-mapping thesis' arithmetic mean (3.2.3), each technique that can produce
// the sample weighted equally.
enum class MisHeuristic { Balance, Power, Maximum, Mean, None };
inline const EnumTable<MisHeuristic>& mis_names() {
    static const EnumTable<MisHeuristic> t{{{"balance", MisHeuristic::Balance},
                                            {"power", MisHeuristic::Power},
                                            {"max", MisHeuristic::Maximum},
                                            {"maximum", MisHeuristic::Maximum},
                                            {"mean", MisHeuristic::Mean},
                                            {"none", MisHeuristic::None}}};
    return t;
}
inline const char* mis_name(MisHeuristic h) {
    return mis_names().name(h);
}

// rr_depth that no path reaches: Russian roulette off.
inline constexpr uint32_t kNoRoulette = 1000000;

}  // namespace foton
