// What the path tracer's shading kernels share (path_diffuse.cpp, path_specular.cpp): which
// kernel takes a hit, the surface and the random numbers of a chunk of lanes, the chunk loop
// and the read-back (which kernel takes a material: common/kernel_materials.cpp).
#include <algorithm>
#include <bit>

#include "engine/transport/common/surface.h"
#include "kernels/counter_hash.h"
#include "kernels/halton_net.h"
#include "kernels/lane_compress.h"
#include "kernels/sobol_net.h"
#include "kernels/specular_shade.h"
#include "kernels/zsobol_net.h"
#include "path.h"

namespace foton {

namespace {

kern::DiffuseMis kernel_mis(MisHeuristic h) {
    switch (h) {
        case MisHeuristic::Balance:
            return kern::DiffuseMis::Balance;
        case MisHeuristic::Power:
            return kern::DiffuseMis::Power;
        case MisHeuristic::Maximum:
            return kern::DiffuseMis::Maximum;
        case MisHeuristic::Mean:
            return kern::DiffuseMis::Mean;
        case MisHeuristic::None:
            break;
    }
    return kern::DiffuseMis::None;
}

}  // namespace

// The scene's kernel materials, and whether this tracer's vertex rules let the kernels shade.
KernelMaterials PathIntegrator::kernel_materials() const {
    KernelMaterials d = foton::kernel_materials(ctx_.scene);
    const RenderSettings& rs = ctx_.settings;
    const VertexRules plain = VertexRules::path(rs);
    // Only the plain path tracer's vertices: the distributed tracer, guided paths, the
    // lighting split and power heuristics of another exponent than 2 keep their own rules in
    // shade_vertex.
    const bool power2 = rules_.mis.heuristic != MisHeuristic::Power || rules_.mis.beta == 2.f;
    d.enabled = rs.simd_shading && !rs.regularize && !rules_.ambient && !rules_.every_light &&
                !rules_.glossy_by_sampling && !rules_.emission_whole &&
                rules_.continue_lobes == plain.continue_lobes && !guide_ &&
                rs.lighting == Lighting::All && power2;
    d.rules.mis = kernel_mis(rules_.mis.heuristic);
    return d;
}

KernelKind PathIntegrator::kernel_of(const PathWorkspace& ws, std::size_t i) const {
    const uint32_t geom = ws.hits.geom[i];
    if (geom == kNoHit) return KernelKind::None;
    const KernelKind k = kernels_.object_kernel[geom];
    // The cache's first Lambertian vertex is shade_cached's.
    if (k == KernelKind::Diffuse && cache_ && ws.chain_specular[ws.rays.id[i]] &&
        kernels_.object_lambertian[geom])
        return KernelKind::None;
    return k;
}

// The lane's surface: the hit for the kernel to rebuild, or, for an instance or when the
// caller needs the point now (`need_point`), surface_at's, written whole. True when `sp`
// holds it.
bool PathIntegrator::put_surface(std::size_t lane, std::size_t i, PathWorkspace& ws,
                                 bool need_point, SurfacePoint& sp) const {
    if (!need_point && put_hit(ws.lanes, lane, ctx_.scene, ws.rays, ws.hits, i)) return false;
    sp = surface_at(ctx_.scene, ws.rays, ws.hits, i);
    foton::put_surface(ws.lanes, lane, sp);
    return true;
}

uint32_t PathIntegrator::put_path(std::size_t lane, PathWorkspace& ws) const {
    KernelLanes& L = ws.lanes;
    const std::size_t i = L.entry[lane];
    const uint32_t slot = ws.rays.id[i];
    ws.path_length[slot] += ws.hits.t[i];
    L.put3(kern::kDvWox, lane, -ws.rays.direction(i));
    L.put3(kern::kDvBetaR, lane, ws.beta[slot]);
    L.col(kern::kDvEtaScale)[lane] = ws.eta_scale[slot];
    return slot;
}

float PathIntegrator::lane_number(const PathWorkspace& ws, std::size_t lane, uint32_t row,
                                  uint32_t depth, uint32_t k) const {
    const KernelLanes& L = ws.lanes;
    return L.drawn ? L.rand()[row * KernelLanes::kLanes + lane]
                   : rand(ws, ws.rays.id[L.entry[lane]], depth, k);
}

Point2 PathIntegrator::lane_number2(const PathWorkspace& ws, std::size_t lane, uint32_t row,
                                    uint32_t depth, uint32_t k) const {
    const KernelLanes& L = ws.lanes;
    if (!L.drawn) return rand2(ws, ws.rays.id[L.entry[lane]], depth, k);
    return {L.rand()[row * KernelLanes::kLanes + lane],
            L.rand()[(row + 1) * KernelLanes::kLanes + lane]};
}

// The chunk's random numbers as one table when every lane's sampler is counter-based
// (kern::uniform_table), Sobol' (kern::sobol::sample_table), Z-Sobol'
// (kern::zsobol::sample_table) or Halton (kern::halton::sample_table): the same numbers
// rand() gives one at a time.
void PathIntegrator::draw_lane_numbers(uint32_t depth, PathWorkspace& ws) const {
    KernelLanes& L = ws.lanes;
    L.drawn = false;
    const PathSampler& first = ws.samplers[ws.rays.id[L.entry[0]]];
    const bool uniform = first.counter_based(), sobol = first.sobol(), z = first.zsobol(),
               halton = first.halton();
    if (!uniform && !sobol && !z && !halton) return;
    for (std::size_t k = 0; k < L.size; ++k) {
        const PathSampler& ps = ws.samplers[ws.rays.id[L.entry[k]]];
        if (ps.counter_based() != uniform || ps.sobol() != sobol || ps.zsobol() != z ||
            ps.halton() != halton || (uniform && ps.prefix() != first.prefix()))
            return;
        if (z) {
            L.z_index[k] = ps.z_index().index;
            L.z_bits[k] = ps.z_index().bits;
            L.keys[k] = ps.z_index().key;
        } else {
            L.keys[k] = ps.key();
            L.pattern_index[k] = ps.pattern_index();
            L.pattern_count[k] = ps.pattern_count();
        }
    }
    // The kernels read up to 16 lanes past the last: one-point patterns there.
    const std::size_t padded = (L.size + 15) / 16 * 16;
    for (std::size_t k = L.size; k < padded; ++k) {
        L.keys[k] = 0;
        L.z_index[k] = 0;
        L.pattern_index[k] = 0;
        L.pattern_count[k] = 1;
        L.z_bits[k] = 0;
    }
    const uint32_t p0 = 1 + depth * 4;
    const uint32_t pairs[4] = {p0, p0 + 1, p0 + 2, p0 + 3};
    // The rows' dimensions (path_sampler.h): light point, BSDF direction, light choice,
    // triangle, lobe, roulette.
    const uint64_t base = uint64_t(depth) * kPathDimsPerBounce;
    const uint64_t dims[KernelLanes::kRandRows] = {
        base + kPathDimLight,    base + kPathDimLight + 1,   base + kPathDimBsdf + 1,
        base + kPathDimBsdf + 2, base + kPathDimLightSelect, base + kPathDimLight + 2,
        base + kPathDimBsdf,     base + kPathDimRoulette};
    if (uniform) {
        kern::uniform_table(first.prefix(), L.keys.data(), L.size, dims, KernelLanes::kRandRows,
                            L.rand(), KernelLanes::kLanes);
    } else if (halton) {
        // The path's dimensions follow the pixel's two (PathSampler::get1).
        uint32_t hdims[KernelLanes::kRandRows];
        for (uint32_t r = 0; r < KernelLanes::kRandRows; ++r) hdims[r] = uint32_t(2 + dims[r]);
        kern::halton::sample_table(ctx_.seed, L.pattern_index.data(), L.keys.data(), L.size, hdims,
                                   KernelLanes::kRandRows, L.rand(), KernelLanes::kLanes);
    } else if (sobol) {
        kern::sobol::sample_table(ctx_.seed, L.pattern_index.data(), L.pattern_count.data(),
                                  L.keys.data(), L.size, pairs, 4, L.rand(), KernelLanes::kLanes);
    } else {
        kern::zsobol::sample_table(L.z_index.data(), L.z_bits.data(), L.keys.data(), L.size, pairs,
                                   4, L.rand(), KernelLanes::kLanes);
    }
    L.drawn = true;
}

void PathIntegrator::read_lanes(PathWorkspace& ws, bool delta) const {
    KernelLanes& L = ws.lanes;
    const float* shadow_valid = L.col(kern::kDvShadowValid);
    const float* next_valid = L.col(kern::kDvNextValid);
    // The vertex's normal is only read where the light BVH weighs an emitter hit's pick.
    const bool keep_normal = ctx_.lights.selection() == LightSelection::Bvh;
    std::size_t shadows = 0, nexts = 0;
    for (std::size_t k = 0; k < L.size; ++k) {
        shadows += shadow_valid[k] != 0.f;
        nexts += next_valid[k] != 0.f;
        L.slots[k] = ws.rays.id[L.entry[k]];
    }
    auto words = [&](uint32_t c) { return reinterpret_cast<const uint32_t*>(L.col(c)); };
    auto out = [](AlignedVector<float>& v, std::size_t at) {
        return reinterpret_cast<uint32_t*>(v.data() + at);
    };
    // Both batches grown once and the valid lanes packed into them, column by column.
    const std::size_t s = ws.shadow.size(), n = ws.next.size();
    ws.shadow.resize(s + shadows);
    ws.next.resize(n + nexts);
    RayBatch& sh = ws.shadow;
    const uint32_t* shadow_src[11] = {
        words(kern::kDvSox), words(kern::kDvSoy), words(kern::kDvSoz),   words(kern::kDvSdx),
        words(kern::kDvSdy), words(kern::kDvSdz), words(kern::kDvStmax), L.slots,
        words(kern::kDvSvR), words(kern::kDvSvG), words(kern::kDvSvB)};
    uint32_t* value[3] = {L.packed[0], L.packed[1], L.packed[2]};
    uint32_t* const shadow_dst[11] = {out(sh.ox, s),   out(sh.oy, s),    out(sh.oz, s),
                                      out(sh.dx, s),   out(sh.dy, s),    out(sh.dz, s),
                                      out(sh.tmax, s), sh.id.data() + s, value[0],
                                      value[1],        value[2]};
    kern::compress_lanes(shadow_valid, L.size, shadow_src, shadow_dst, 11);
    std::fill(sh.tmin.begin() + std::ptrdiff_t(s), sh.tmin.end(), 0.f);
    ws.shadow_value.resize(s + shadows);
    for (std::size_t j = 0; j < shadows; ++j)
        ws.shadow_value[s + j] =
            RGB{std::bit_cast<float>(value[0][j]), std::bit_cast<float>(value[1][j]),
                std::bit_cast<float>(value[2][j])};
    RayBatch& nx = ws.next;
    const uint32_t* next_src[7] = {words(kern::kDvNox),
                                   words(kern::kDvNoy),
                                   words(kern::kDvNoz),
                                   words(kern::kDvNdx),
                                   words(kern::kDvNdy),
                                   words(kern::kDvNdz),
                                   L.slots};
    uint32_t* const next_dst[7] = {out(nx.ox, n), out(nx.oy, n), out(nx.oz, n),   out(nx.dx, n),
                                   out(nx.dy, n), out(nx.dz, n), nx.id.data() + n};
    kern::compress_lanes(next_valid, L.size, next_src, next_dst, 7);
    std::fill(nx.tmin.begin() + std::ptrdiff_t(n), nx.tmin.end(), 0.f);
    std::fill(nx.tmax.begin() + std::ptrdiff_t(n), nx.tmax.end(), kInfinity);
    // The continuing paths' state.
    for (std::size_t k = 0; k < L.size; ++k) {
        if (next_valid[k] == 0.f) continue;
        const uint32_t slot = L.slots[k];
        const Vec3 b = L.get3(kern::kDvNbetaR, k);
        ws.beta[slot] = RGB{b.x, b.y, b.z};
        ws.pdf_prev[slot] = L.col(kern::kDvNpdf)[k];
        ws.p_prev[slot] = L.get3(kern::kDvPx, k);
        if (keep_normal) ws.n_prev[slot] = L.get3(kern::kDvNgx, k);
        // shade_vertex's bookkeeping: a delta bounce after the first non-specular vertex
        // makes what it finds a caustic there; any other bounce counts one more vertex.
        ws.specular_prev[slot] = delta;
        if (delta) {
            ws.eta_scale[slot] = L.col(kern::kDvNetaScale)[k];
            if (ws.nondelta[slot] == 1) ws.nondelta[slot] = 2;
        } else {
            ws.nondelta[slot] = uint8_t(std::min(2, ws.nondelta[slot] + 1));
            ws.chain_specular[slot] = 0;
        }
    }
}

// Under the light BVH, the chunk's surfaces first and then every lane's light in one call of
// the descent kernel (the same picks as shade_vertex's one at a time).
void PathIntegrator::pick_lane_lights(uint32_t depth, PathWorkspace& ws) const {
    KernelLanes& L = ws.lanes;
    if (!rules_.nee || ctx_.lights.empty() || ctx_.lights.selection() != LightSelection::Bvh)
        return;
    for (std::size_t k = 0; k < L.size; ++k) {
        SurfacePoint& sp = L.surface[k];
        put_surface(k, L.entry[k], ws, true, sp);
        L.picks.put(k,
                    lane_number(ws, k, KernelLanes::kRandLightSelect, depth, kPathDimLightSelect),
                    sp.p, sp.ng);
    }
    ctx_.lights.pick_lanes(L.picks, L.size);
    L.picked = true;
}

void PathIntegrator::shade_lanes(uint32_t depth, KernelKind kind, PathWorkspace& ws) const {
    KernelLanes& L = ws.lanes;
    kern::DiffuseRules rules = kernels_.rules;
    rules.roulette = depth + 1 >= ctx_.settings.rr_depth;
    const std::vector<uint32_t>& entries =
        kind == KernelKind::Diffuse ? ws.diffuse_entries : ws.specular_entries;
    for (std::size_t start = 0; start < entries.size(); start += KernelLanes::kLanes) {
        L.size = std::min(KernelLanes::kLanes, entries.size() - start);
        for (std::size_t k = 0; k < L.size; ++k) L.entry[k] = entries[start + k];
        draw_lane_numbers(depth, ws);
        L.picked = false;
        if (kind == KernelKind::Diffuse) pick_lane_lights(depth, ws);
        for (std::size_t k = 0; k < L.size; ++k) {
            if (kind == KernelKind::Diffuse)
                fill_diffuse_lane(depth, k, ws);
            else
                fill_specular_lane(depth, k, ws);
        }
        // The lanes past the last up to the SIMD width are computed too and never read back.
        // They hold whatever earlier chunks left there (at first the table's zeros); no
        // lane's result depends on another lane's values, so they are not cleared (clearing
        // every column cost 1 % of a render).
        if (kind == KernelKind::Diffuse)
            kern::shade_diffuse(L.table(), L.size, rules);
        else
            kern::shade_specular(L.table(), L.size, rules.roulette);
        read_lanes(ws, kind == KernelKind::Specular);
    }
}

}  // namespace foton
