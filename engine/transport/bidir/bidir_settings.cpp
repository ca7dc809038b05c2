#include "bidir_settings.h"

#include <cstdio>
#include <string>

namespace foton {

void parse_bidir_settings(const ParamSet& p, const IntegratorTraits& it, MisHeuristic& mis,
                          BidirSettings& b) {
    // A scene written for another integrator may carry what bdpt, bpm and vcm do not take:
    // warned about at its line and ignored, so it renders.
    const std::string running = std::string("; ignored by type=\"") + it.name + "\"";
    const bool bidir = it.has(kCapBidirectional);
    if (bidir && mis != MisHeuristic::Balance && mis != MisHeuristic::Power) {
        p.warn("mis", std::string("mis=") + mis_name(mis) +
                          " is path tracing's; bdpt, bpm and vcm weigh by the balance or power "
                          "heuristic (power used)" +
                          running);
        mis = MisHeuristic::Power;
    }
    // Roulette by depth would differ between the two subpaths' view of a vertex.
    if (bidir && p.has("rr_depth"))
        p.warn("rr_depth",
               "bdpt, bpm and vcm continue a subpath with the vertex's albedo estimate at every "
               "vertex (MIS needs a rule that does not depend on depth): rr_depth does not "
               "apply" +
                   running);
    static const EnumTable<MergeIndex> kMergeIndex{
        {{"grid", MergeIndex::Grid}, {"kdtree", MergeIndex::KdTree}}};
    b.merge_index = p.choice("merge_index", kMergeIndex, b.merge_index);
    if (p.has("merge_index") && !it.has(kCapMerging)) {
        p.warn("merge_index", "merge_index applies to " + it.names_with(kCapMerging) + running);
        b.merge_index = MergeIndex::Grid;
    }
    if (p.has("strategy_images")) {
        b.strategy_images = uint32_t(p.integer("strategy_images", 0, 0, 12));
        if (b.strategy_images == 1)
            p.fail("strategy_images",
                   "strategy_images is the longest path (in vertices, at "
                   "least 2: a light seen directly) whose strategies get a "
                   "layer each; 0: none");
        if (!bidir) {
            p.warn("strategy_images",
                   "strategy_images applies to " + it.names_with(kCapBidirectional) + running);
            b.strategy_images = 0;
        }
    }
    if (!p.has("strategy")) return;
    const std::string v = p.text("strategy");
    if (!it.has(kCapStrategyDebug)) {
        p.warn("strategy",
               "strategy=\"s,t\" applies to " + it.names_with(kCapStrategyDebug) + running);
        return;
    }
    unsigned s = 0, t = 0;
    char tail = 0;
    if (v != "all") {
        if (std::sscanf(v.c_str(), "%u,%u%c", &s, &t, &tail) != 2 || t < 1 || s + t < 2 ||
            s > 1000 || t > 1000)
            p.fail("strategy",
                   "strategy is \"all\" or \"s,t\": s >= 0 light vertices and t "
                   ">= 1 camera vertices (e.g. \"1,2\": next event estimation at "
                   "the first hit), not '" +
                       v + "'");
        b.only_s = int(s);
        b.only_t = int(t);
    }
}

}  // namespace foton
