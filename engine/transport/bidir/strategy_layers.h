#pragma once
// Per-strategy images (strategy_images=L, bdpt, bpm and vcm): what each strategy adds to the
// image, with its MIS weight, as a layer of its own: strategy (s, t) (s light and t camera
// vertices) of every path of at most L vertices, one layer for the strategies of longer
// paths and one for the merges, so the layers add up to the image. Veach's thesis (fig. 10.3)
// and pbrt's bdpt show these to see which strategy carries which light.
#include <cstdint>
#include <string>

namespace foton {

struct StrategyLayers {
    uint32_t max_vertices = 0;  // L; 0: no layers
    bool merging = false;       // a merge layer (bpm, vcm)

    bool enabled() const { return max_vertices >= 2; }
    // Layers of paths of n <= L vertices: s = 0 ... n - 1 for each n = 2 ... L.
    uint32_t longer() const { return max_vertices * (max_vertices + 1) / 2 - 1; }
    uint32_t merges() const { return longer() + 1; }
    uint32_t count() const { return enabled() ? merges() + (merging ? 1 : 0) : 0; }
    // The layer of strategy (s, t).
    uint32_t of(int s, int t) const {
        const uint32_t n = uint32_t(s + t);
        return n > max_vertices ? longer() : n * (n - 1) / 2 - 1 + uint32_t(s);
    }
    // "strategy_s1_t2", "strategy_longer", "strategy_merges".
    std::string name(uint32_t layer) const {
        if (layer == longer()) return "strategy_longer";
        if (layer == merges()) return "strategy_merges";
        uint32_t n = 2;
        while (n * (n + 1) / 2 - 1 <= layer) ++n;
        const uint32_t s = layer - (n * (n - 1) / 2 - 1);
        return "strategy_s" + std::to_string(s) + "_t" + std::to_string(n - s);
    }
};

}  // namespace foton
