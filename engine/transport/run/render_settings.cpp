#include "render_settings.h"

#include <cstdio>

namespace foton {

namespace {

constexpr uint64_t kMaxCount = kMaxSamplesPerPass;
const EnumTable<Lighting> kLighting{
    {{"all", Lighting::All}, {"direct", Lighting::Direct}, {"indirect", Lighting::Indirect}}};

void parse_sampling(const ParamSet& p, RenderSettings& r) {
    // aa_samples is the first thesis' name; spp (and --spp, which sets it) wins over it.
    r.run.spp = uint32_t(p.integer("aa_samples", r.run.spp, 1, kMaxCount));
    r.run.spp = uint32_t(p.integer("spp", r.run.spp, 1, kMaxCount));
    r.run.threads = int(p.integer("num_threads", 0, 0, kMaxThreads));
    r.sampler = p.choice("sampler", sampler_names(), r.sampler);
    r.max_depth = uint32_t(p.integer("max_depth", r.max_depth, 0, 1000));
    r.min_contribution = p.real("min_contribution", r.min_contribution, 0.f);
    r.run.seed = p.integer("seed", r.run.seed);
    r.run.time_limit = p.real("time", 0.f, 0.f);
    AdaptiveSettings& ad = r.adaptive;
    ad.enabled = p.boolean("adaptive", ad.enabled);
    ad.pilot = uint32_t(p.integer("adaptive_pilot", ad.pilot, 1, kMaxCount));
    ad.max_spp = uint32_t(p.integer("adaptive_max_spp", ad.max_spp, 1, kMaxCount));
    ad.threshold = p.positive("adaptive_threshold", ad.threshold);
    ad.unbiased = p.boolean("adaptive_unbiased", ad.unbiased);
    if (ad.max_spp < ad.pilot) p.fail("adaptive_max_spp", "max_spp must be at least pilot");
}

void parse_path(const ParamSet& p, RenderSettings& r) {
    r.mis = p.choice("mis", mis_names(), r.mis, "mis heuristic");
    r.mis_beta = p.real("mis_beta", r.mis_beta, 1.f, 16.f);
    if (p.has("mis_beta") && r.mis != MisHeuristic::Power)
        p.fail("mis_beta", "mis_beta is the power heuristic's exponent: it needs mis=power");
    r.nee = p.boolean("nee", r.nee);
    r.rr_depth = uint32_t(p.integer("rr_depth", r.rr_depth, 0, kNoRoulette));
    r.light_samples = uint32_t(p.integer("light_samples", r.light_samples, 1, kMaxCount));
}

void parse_path_guide(const ParamSet& p, const IntegratorTraits& it, RenderSettings& r) {
    PathGuideSettings& g = r.guide;
    g.enabled = p.boolean("guided", g.enabled);
    g.emitted = p.integer("guide_emitted", g.emitted, 1, 4000000000ull);
    g.cells = uint32_t(p.integer("guide_cells", g.cells, 1, kMaxGuideCells));
    g.min_photons = uint32_t(p.integer("guide_min_photons", g.min_photons, 1, 1000000));
    g.fraction = p.real("guide_fraction", g.fraction, 0.f, 0.99f);
    if (!g.enabled) {
        for (const char* key :
             {"guide_emitted", "guide_cells", "guide_min_photons", "guide_fraction"})
            if (p.has(key)) p.fail(key, std::string(key) + " needs guided=true");
        return;
    }
    if (!(it.caps & kCapPhotonGuide))
        p.fail("guided", "guided=true needs " + it.names_with(kCapPhotonGuide));
    // Roulette on a guided path throws away what the guide bought: its variance grows with
    // the square of the continuation's mean, which guiding does not lower. Measured on the
    // caustics box (docs/results.md): no roulette is 1.9x as efficient as rr_depth=3 when guided.
    if (!p.has("rr_depth")) r.rr_depth = kNoRoulette;
}

void parse_bidir(const ParamSet& p, const IntegratorTraits& it, RenderSettings& r) {
    const bool bidir = it.caps & kCapBidirectional;
    if (bidir && r.mis != MisHeuristic::Balance && r.mis != MisHeuristic::Power)
        p.fail("mis",
               "bdpt, bpm and vcm weigh by the balance or power heuristic (mis=balance "
               "or mis=power)");
    // Roulette by depth would differ between the two subpaths' view of a vertex.
    if (bidir && p.has("rr_depth"))
        p.fail("rr_depth",
               "bdpt, bpm and vcm continue a subpath with the vertex's albedo "
               "estimate at every vertex (MIS needs a rule that does not depend on "
               "depth): rr_depth does not apply");
    static const EnumTable<MergeIndex> kMergeIndex{
        {{"grid", MergeIndex::Grid}, {"kdtree", MergeIndex::KdTree}}};
    r.bidir.merge_index = p.choice("merge_index", kMergeIndex, r.bidir.merge_index);
    if (p.has("merge_index") && !(it.caps & kCapMerging))
        p.fail("merge_index", "merge_index needs " + it.names_with(kCapMerging));
    if (!p.has("strategy")) return;
    const std::string v = p.text("strategy");
    if (!(it.caps & kCapStrategyDebug))
        p.fail("strategy", "strategy=\"s,t\" needs " + it.names_with(kCapStrategyDebug));
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
        r.bidir.only_s = int(s);
        r.bidir.only_t = int(t);
    }
}

}  // namespace

RenderSettings parse_render_settings(const ParamSet& params, const IntegratorTraits& it) {
    RenderSettings r;
    r.integrator = it.name;
    parse_sampling(params, r);
    parse_path(params, r);
    parse_photon_settings(params, r.photon);
    parse_cache_settings(params, r.indirect, r.cache);
    parse_path_guide(params, it, r);
    parse_bidir(params, it, r);
    r.lighting = params.choice("lighting", kLighting, r.lighting);
    if (r.lighting != Lighting::All) {
        if (!(it.caps & kCapLightingSplit))
            params.fail("lighting",
                        "lighting=direct|indirect needs " + it.names_with(kCapLightingSplit));
        if (r.indirect == IndirectMode::IrradianceCache)
            params.fail("lighting",
                        "lighting=direct|indirect and indirect=\"irradiance_cache\" "
                        "do not combine");
    }
    if (r.guide.enabled && r.indirect == IndirectMode::IrradianceCache)
        params.fail("guided", "guided paths and indirect=\"irradiance_cache\" do not combine");
    return r;
}

}  // namespace foton
