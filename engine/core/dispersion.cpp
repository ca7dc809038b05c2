#include "dispersion.h"

namespace foton {

namespace {

constexpr double kLineD = 587.5618, kLineF = 486.1327, kLineC = 656.2725;  // nm

struct Glass {
    const char* name;
    float nd, vd;  // SCHOTT's catalogue: index at the d line, Abbe number
};

constexpr Glass kGlasses[] = {
    {"glass-BK7", 1.5168f, 64.17f},   {"glass-BAF10", 1.6700f, 47.11f},
    {"glass-FK51A", 1.4866f, 84.47f}, {"glass-LASF9", 1.8503f, 32.17f},
    {"glass-F5", 1.6034f, 38.03f},
};

}  // namespace

Dispersion Dispersion::from_abbe(float nd, float vd) {
    // n_F - n_C = b (1/F^2 - 1/C^2) = (n_d - 1) / V_d; a puts n(d) at n_d.
    const double spread = (double(nd) - 1.0) / double(vd);
    const double b = spread / (1.0 / (kLineF * kLineF) - 1.0 / (kLineC * kLineC));
    Dispersion d;
    d.b = float(b);
    d.a = float(double(nd) - b / (kLineD * kLineD));
    return d;
}

bool named_glass(const std::string& name, Dispersion& out) {
    for (const Glass& g : kGlasses)
        if (name == g.name) {
            out = Dispersion::from_abbe(g.nd, g.vd);
            return true;
        }
    return false;
}

}  // namespace foton
