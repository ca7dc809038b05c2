#pragma once
// Multiple importance sampling weights for two techniques with one sample each (Veach
// 1997): the weight of the technique that produced a sample with density pa, when the other
// would have produced it with density pb.
#include <cmath>

#include "transport_settings.h"

namespace foton {

inline constexpr float kMaxTieTolerance = 1.f + 1e-3f;

// A heuristic with its parameter: the power heuristic's exponent beta (Veach's 2 by
// default; 1 is the balance heuristic, larger values approach the maximum heuristic).
struct Mis {
    MisHeuristic heuristic = MisHeuristic::Power;
    float beta = 2.f;
};

inline float mis_weight(const Mis& m, float pa, float pb) {
    switch (m.heuristic) {
        case MisHeuristic::Balance:
            return pa / (pa + pb);
        case MisHeuristic::Power: {
            if (m.beta == 2.f) {
                const float a = pa * pa, b = pb * pb;
                return a / (a + b);
            }
            // 1 / (1 + (pb / pa)^beta): no overflow of pa^beta for large densities.
            if (!(pa > 0.f)) return 0.f;
            return 1.f / (1.f + std::pow(pb / pa, m.beta));
        }
        case MisHeuristic::Maximum:
            // Ties go to the first technique (callers pass light sampling first). A tie is
            // common, not rare: area-sampling a sphere from its own surface has exactly the
            // cosine density. The two sides compute the pdfs from different points (sampled
            // vs hit), so a tie must be declared with a tolerance above float noise, or both
            // weights can be zero.
            return pa * kMaxTieTolerance >= pb ? 1.f : 0.f;
        case MisHeuristic::Mean:
            // The average of the techniques that can produce the sample: 1/2 each where both
            // can, all of it where the other cannot (the weights still sum to one).
            return pb > 0.f ? 0.5f : 1.f;
        case MisHeuristic::None:
            return 1.f;
    }
    return 1.f;
}

// The BSDF technique's weight: strict > so that a tie goes to light sampling.
inline float mis_weight_bsdf(const Mis& m, float p_bsdf, float p_light) {
    if (m.heuristic == MisHeuristic::Maximum)
        return p_bsdf > p_light * kMaxTieTolerance ? 1.f : 0.f;
    return mis_weight(m, p_bsdf, p_light);
}

}  // namespace foton
