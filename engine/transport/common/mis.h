#pragma once
// Multiple importance sampling weights for two techniques with one sample each (Veach
// 1997): the weight of the technique that produced a sample with density pa, when the other
// would have produced it with density pb.
#include "engine/core/params.h"

namespace foton {

// How next event estimation and BSDF sampling are combined in `path`.
enum class MisHeuristic { Balance, Power, Maximum, None };
inline const EnumTable<MisHeuristic>& mis_names() {
    static const EnumTable<MisHeuristic> t{{{"balance", MisHeuristic::Balance},
                                            {"power", MisHeuristic::Power},
                                            {"max", MisHeuristic::Maximum},
                                            {"maximum", MisHeuristic::Maximum},
                                            {"none", MisHeuristic::None}}};
    return t;
}
inline const char* mis_name(MisHeuristic h) {
    return mis_names().name(h);
}

inline constexpr float kMaxTieTolerance = 1.f + 1e-3f;

inline float mis_weight(MisHeuristic h, float pa, float pb) {
    switch (h) {
        case MisHeuristic::Balance:
            return pa / (pa + pb);
        case MisHeuristic::Power: {
            const float a = pa * pa, b = pb * pb;  // beta = 2
            return a / (a + b);
        }
        case MisHeuristic::Maximum:
            // Ties go to the first technique (callers pass light sampling first). A tie is
            // common, not rare: area-sampling a sphere from its own surface has exactly the
            // cosine density. The two sides compute the pdfs from different points (sampled
            // vs hit), so a tie must be declared with a tolerance above float noise, or both
            // weights can be zero.
            return pa * kMaxTieTolerance >= pb ? 1.f : 0.f;
        case MisHeuristic::None:
            return 1.f;
    }
    return 1.f;
}

// The BSDF technique's weight: strict > so that a tie goes to light sampling.
inline float mis_weight_bsdf(MisHeuristic h, float p_bsdf, float p_light) {
    if (h == MisHeuristic::Maximum) return p_bsdf > p_light * kMaxTieTolerance ? 1.f : 0.f;
    return mis_weight(h, p_bsdf, p_light);
}

}  // namespace foton
