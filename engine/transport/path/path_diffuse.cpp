// The path tracer's Lambertian vertices through kern::shade_diffuse: a chunk of lanes is
// filled from the batch (surface, throughput, the light sample, the random numbers), shaded
// at SIMD width, and read back into shadow rays, continuation rays and the paths' state.
// What stays scalar here: reconstructing the surface, choosing and sampling the light, the
// sampler's numbers.
#include <algorithm>
#include <cmath>

#include "engine/transport/common/surface.h"
#include "kernels/sobol_net.h"
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
        case MisHeuristic::None:
            break;
    }
    return kern::DiffuseMis::None;
}

// Every lobe Lambertian (their sum is one Lambertian lobe of the summed reflectance), no
// texture, no emission: a vertex the kernel shades exactly as shade_vertex would.
bool kernel_material(const Material& m, RGB& rho) {
    if (m.texture >= 0 || !m.emission.is_black() || m.bsdf.empty()) return false;
    rho = RGB{0.f};
    for (int i = 0; i < m.bsdf.size(); ++i) {
        const Lobe& l = m.bsdf.lobe(i);
        if (l.type != LobeType::Lambert) return false;
        rho += l.color;
    }
    return true;
}

}  // namespace

DiffuseMaterials PathIntegrator::diffuse_materials() const {
    DiffuseMaterials d;
    const RenderSettings& rs = ctx_.settings;
    const VertexRules plain = VertexRules::path(rs);
    // Only the plain path tracer's vertices: the distributed tracer, guided paths, the
    // lighting split and power heuristics of another exponent than 2 keep their own rules in
    // shade_vertex.
    const bool power2 = rules_.mis.heuristic != MisHeuristic::Power || rules_.mis.beta == 2.f;
    d.enabled = rs.simd_shading && !rules_.ambient && !rules_.every_light &&
                !rules_.glossy_by_sampling && !rules_.emission_whole &&
                rules_.continue_lobes == plain.continue_lobes && !guide_ &&
                rs.lighting == Lighting::All && power2;
    d.rules.mis = kernel_mis(rules_.mis.heuristic);
    const std::vector<Material>& ms = ctx_.scene.materials;
    d.takes.assign(ms.size(), 0);
    d.rho.assign(ms.size(), RGB{0.f});
    for (std::size_t k = 0; k < ms.size(); ++k) d.takes[k] = kernel_material(ms[k], d.rho[k]);
    return d;
}

bool PathIntegrator::diffuse_kernel_takes(const PathWorkspace& ws, std::size_t i) const {
    const uint32_t geom = ws.hits.geom[i];
    if (geom == kNoHit || !diffuse_.takes[ctx_.scene.objects[geom].material]) return false;
    // The cache's first diffuse vertex is shade_cached's.
    return !(cache_ && ws.chain_specular[ws.rays.id[i]]);
}

// The hit's geometry for the kernel to reconstruct the surface from (flat and smooth
// triangles of meshes placed as they are, spheres); false for an instance, whose surface
// surface_at makes here.
bool PathIntegrator::put_hit(std::size_t lane, std::size_t i, PathWorkspace& ws) const {
    DiffuseLanes& L = ws.diffuse;
    const Scene& scene = ctx_.scene;
    const Object& obj = scene.objects[ws.hits.geom[i]];
    if (obj.instance >= 0) return false;
    auto put3 = [&](uint32_t c, const Vec3& a) {
        L.col(c)[lane] = a.x;
        L.col(c + 1)[lane] = a.y;
        L.col(c + 2)[lane] = a.z;
    };
    float kind;
    if (obj.kind == ObjectKind::Mesh) {
        const TriangleMesh& m = scene.meshes[obj.index];
        const uint32_t* ix = &m.indices[3 * std::size_t(ws.hits.prim[i])];
        put3(kern::kDvA0x, m.vertex(ix[0]));
        put3(kern::kDvA1x, m.vertex(ix[1]));
        put3(kern::kDvA2x, m.vertex(ix[2]));
        kind = 1.f;
        if (obj.smooth) {
            put3(kern::kDvN0x, m.vertex_normal(ix[0]));
            put3(kern::kDvN1x, m.vertex_normal(ix[1]));
            put3(kern::kDvN2x, m.vertex_normal(ix[2]));
            kind = 2.f;
        }
    } else {
        const Sphere& sph = scene.spheres[obj.index];
        put3(kern::kDvA0x, sph.center);
        L.col(kern::kDvA1x)[lane] = sph.radius;
        put3(kern::kDvOx, ws.rays.origin(i));
        kind = 3.f;
    }
    L.col(kern::kDvSurface)[lane] = kind;
    L.col(kern::kDvT)[lane] = ws.hits.t[i];
    L.col(kern::kDvU)[lane] = ws.hits.u[i];
    L.col(kern::kDvV)[lane] = ws.hits.v[i];
    return true;
}

// The chunk's random numbers as one table when every lane's sampler is counter-based
// (kern::uniform_table), Sobol' (kern::sobol::sample_table) or Z-Sobol'
// (kern::zsobol::sample_table): the same numbers rand() gives one at a time. Halton draws
// them one at a time in the fill.
void PathIntegrator::draw_diffuse_numbers(uint32_t depth, PathWorkspace& ws) const {
    DiffuseLanes& L = ws.diffuse;
    L.drawn = false;
    const PathSampler& first = ws.samplers[ws.rays.id[L.entry[0]]];
    const bool uniform = first.counter_based(), sobol = first.sobol(), z = first.zsobol();
    if (!uniform && !sobol && !z) return;
    for (std::size_t k = 0; k < L.size; ++k) {
        const PathSampler& ps = ws.samplers[ws.rays.id[L.entry[k]]];
        if (ps.counter_based() != uniform || ps.sobol() != sobol || ps.zsobol() != z ||
            (uniform && ps.prefix() != first.prefix()))
            return;
        if (z) {
            L.z_index[k] = ps.z_index().index;
            L.pattern_count[k] = ps.z_index().bits;
            L.keys[k] = ps.z_index().key;
        } else {
            L.keys[k] = ps.key();
            L.pattern_index[k] = ps.pattern_index();
            L.pattern_count[k] = ps.pattern_count();
        }
    }
    // The kernels read up to 8 lanes past the last: one-point patterns there.
    const std::size_t padded = (L.size + 7) / 8 * 8;
    for (std::size_t k = L.size; k < padded; ++k) {
        L.keys[k] = 0;
        L.z_index[k] = 0;
        L.pattern_index[k] = 0;
        L.pattern_count[k] = 1;
    }
    const uint32_t p0 = 1 + depth * 4;
    const uint32_t pairs[4] = {p0, p0 + 1, p0 + 2, p0 + 3};
    if (uniform) {
        // The rows' dimensions (path_sampler.h): light point, BSDF direction, light choice,
        // triangle, lobe, roulette.
        const uint64_t base = uint64_t(depth) * kPathDimsPerBounce;
        const uint64_t dims[DiffuseLanes::kRandRows] = {
            base + kPathDimLight,    base + kPathDimLight + 1,   base + kPathDimBsdf + 1,
            base + kPathDimBsdf + 2, base + kPathDimLightSelect, base + kPathDimLight + 2,
            base + kPathDimBsdf,     base + kPathDimRoulette};
        kern::uniform_table(first.prefix(), L.keys.data(), L.size, dims, DiffuseLanes::kRandRows,
                            L.rand.data(), DiffuseLanes::kLanes);
    } else if (sobol) {
        kern::sobol::sample_table(ctx_.seed, L.pattern_index.data(), L.pattern_count.data(),
                                  L.keys.data(), L.size, pairs, 4, L.rand.data(),
                                  DiffuseLanes::kLanes);
    } else {
        kern::zsobol::sample_table(L.z_index.data(), L.pattern_count.data(), L.keys.data(), L.size,
                                   pairs, 4, L.rand.data(), DiffuseLanes::kLanes);
    }
    L.drawn = true;
}

void PathIntegrator::fill_diffuse_lane(uint32_t depth, std::size_t lane, PathWorkspace& ws) const {
    DiffuseLanes& L = ws.diffuse;
    const std::size_t i = L.entry[lane];
    const uint32_t slot = ws.rays.id[i];
    // Number `row` of the drawn table, or the sampler's number k.
    auto draw = [&](uint32_t row, uint32_t k) {
        return L.drawn ? L.rand[row * DiffuseLanes::kLanes + lane] : rand(ws, slot, depth, k);
    };
    auto draw2 = [&](uint32_t row, uint32_t k) {
        return L.drawn ? Point2{L.rand[row * DiffuseLanes::kLanes + lane],
                                L.rand[(row + 1) * DiffuseLanes::kLanes + lane]}
                       : rand2(ws, slot, depth, k);
    };
    ws.path_length[slot] += ws.hits.t[i];
    auto put3 = [&](uint32_t c, float x, float y, float z) {
        L.col(c)[lane] = x;
        L.col(c + 1)[lane] = y;
        L.col(c + 2)[lane] = z;
    };
    put3(kern::kDvWox, -ws.rays.dx[i], -ws.rays.dy[i], -ws.rays.dz[i]);
    const RGB& rho = diffuse_.rho[ctx_.scene.objects[ws.hits.geom[i]].material];
    put3(kern::kDvRhoR, rho.r, rho.g, rho.b);
    const RGB& beta = ws.beta[slot];
    put3(kern::kDvBetaR, beta.r, beta.g, beta.b);
    L.col(kern::kDvEtaScale)[lane] = ws.eta_scale[slot];
    // The light, as shade_vertex's next event estimation chooses it. The kernel samples a
    // rectangle and makes the surface itself; any other light is sampled here, from the
    // surface point surface_at makes here.
    const bool nee = rules_.nee && !ctx_.lights.empty();
    float pick = 0.f;
    const uint32_t li =
        nee ? ctx_.lights.select(draw(DiffuseLanes::kRandLightSelect, kPathDimLightSelect), pick)
            : 0;
    const Emitter* e = nee ? &ctx_.lights.emitter(li) : nullptr;
    const bool rect = e && e->type == EmitterType::Rect;
    SurfacePoint sp;
    const bool made_here = !(rect || !e) || !put_hit(lane, i, ws);
    if (made_here) {
        sp = surface_at(ctx_.scene, ws.rays, ws.hits, i);
        L.col(kern::kDvSurface)[lane] = 0.f;
        put3(kern::kDvPx, sp.p.x, sp.p.y, sp.p.z);
        put3(kern::kDvNgx, sp.ng.x, sp.ng.y, sp.ng.z);
        put3(kern::kDvNsx, sp.ns.x, sp.ns.y, sp.ns.z);
        L.col(kern::kDvEps)[lane] = sp.epsilon;
    }
    float pdf = 0.f, full = 1.f;
    const bool no_mis = rules_.mis.heuristic == MisHeuristic::None;
    LightSample ls;
    if (rect) {
        const Point2 ul = draw2(DiffuseLanes::kRandLight, kPathDimLight);
        pdf = pick;
        full = no_mis ? 1.f : 0.f;
        ls.p_light = e->p;
        ls.n_light = e->n;
        ls.Li = e->value;
        put3(kern::kDvLe1x, e->e1.x, e->e1.y, e->e1.z);
        put3(kern::kDvLe2x, e->e2.x, e->e2.y, e->e2.z);
        L.col(kern::kDvLarea)[lane] = e->area;
        L.col(kern::kDvLu0)[lane] = ul.x;
        L.col(kern::kDvLu1)[lane] = ul.y;
    } else if (e &&
               ctx_.lights.sample_li(li, sp.p, draw2(DiffuseLanes::kRandLight, kPathDimLight),
                                     draw(DiffuseLanes::kRandLightUc, kPathDimLight + 2), ls)) {
        pdf = pick * ls.pdf;
        full = no_mis || e->is_delta() ? 1.f : 0.f;
    }
    L.col(kern::kDvLrect)[lane] = rect ? 1.f : 0.f;
    L.col(kern::kDvLightPdf)[lane] = pdf;
    L.col(kern::kDvLightFull)[lane] = full;
    put3(kern::kDvLwx, ls.wi.x, ls.wi.y, ls.wi.z);
    L.col(kern::kDvLdist)[lane] = ls.dist;
    put3(kern::kDvLpx, ls.p_light.x, ls.p_light.y, ls.p_light.z);
    put3(kern::kDvLnx, ls.n_light.x, ls.n_light.y, ls.n_light.z);
    put3(kern::kDvLiR, ls.Li.r, ls.Li.g, ls.Li.b);
    const Point2 u = draw2(DiffuseLanes::kRandBsdf, kPathDimBsdf + 1);
    L.col(kern::kDvU0)[lane] = u.x;
    L.col(kern::kDvU1)[lane] = u.y;
    L.col(kern::kDvURoulette)[lane] = depth + 1 >= ctx_.settings.rr_depth
                                          ? draw(DiffuseLanes::kRandRoulette, kPathDimRoulette)
                                          : 0.f;
}

void PathIntegrator::read_diffuse_lanes(PathWorkspace& ws) const {
    DiffuseLanes& L = ws.diffuse;
    const float* shadow_valid = L.col(kern::kDvShadowValid);
    const float* next_valid = L.col(kern::kDvNextValid);
    std::size_t shadows = 0, nexts = 0;
    for (std::size_t k = 0; k < L.size; ++k) {
        shadows += shadow_valid[k] != 0.f;
        nexts += next_valid[k] != 0.f;
    }
    // Both batches grown once and written column by column (not a push per ray).
    RayBatch& sb = ws.shadow;
    std::size_t s = sb.size();
    sb.resize(s + shadows);
    ws.shadow_value.resize(s + shadows);
    RayBatch& nb = ws.next;
    std::size_t n = nb.size();
    nb.resize(n + nexts);
    for (std::size_t k = 0; k < L.size; ++k) {
        const uint32_t slot = ws.rays.id[L.entry[k]];
        if (shadow_valid[k] != 0.f) {
            sb.ox[s] = L.col(kern::kDvSox)[k];
            sb.oy[s] = L.col(kern::kDvSoy)[k];
            sb.oz[s] = L.col(kern::kDvSoz)[k];
            sb.dx[s] = L.col(kern::kDvSdx)[k];
            sb.dy[s] = L.col(kern::kDvSdy)[k];
            sb.dz[s] = L.col(kern::kDvSdz)[k];
            sb.tmin[s] = 0.f;
            sb.tmax[s] = L.col(kern::kDvStmax)[k];
            sb.id[s] = slot;
            ws.shadow_value[s] =
                RGB{L.col(kern::kDvSvR)[k], L.col(kern::kDvSvG)[k], L.col(kern::kDvSvB)[k]};
            ++s;
        }
        if (next_valid[k] == 0.f) continue;
        ws.beta[slot] =
            RGB{L.col(kern::kDvNbetaR)[k], L.col(kern::kDvNbetaG)[k], L.col(kern::kDvNbetaB)[k]};
        ws.pdf_prev[slot] = L.col(kern::kDvNpdf)[k];
        ws.specular_prev[slot] = 0;
        ws.nondelta[slot] = uint8_t(std::min(2, ws.nondelta[slot] + 1));
        ws.chain_specular[slot] = 0;
        ws.p_prev[slot] = Vec3{L.col(kern::kDvPx)[k], L.col(kern::kDvPy)[k], L.col(kern::kDvPz)[k]};
        nb.ox[n] = L.col(kern::kDvNox)[k];
        nb.oy[n] = L.col(kern::kDvNoy)[k];
        nb.oz[n] = L.col(kern::kDvNoz)[k];
        nb.dx[n] = L.col(kern::kDvNdx)[k];
        nb.dy[n] = L.col(kern::kDvNdy)[k];
        nb.dz[n] = L.col(kern::kDvNdz)[k];
        nb.tmin[n] = 0.f;
        nb.tmax[n] = kInfinity;
        nb.id[n] = slot;
        ++n;
    }
}

void PathIntegrator::shade_diffuse(uint32_t depth, PathWorkspace& ws) const {
    DiffuseLanes& L = ws.diffuse;
    kern::DiffuseRules rules = diffuse_.rules;
    rules.roulette = depth + 1 >= ctx_.settings.rr_depth;
    const std::size_t width = kern::diffuse_shade_width();
    const std::vector<uint32_t>& entries = ws.diffuse_entries;
    for (std::size_t start = 0; start < entries.size(); start += DiffuseLanes::kLanes) {
        L.size = std::min(DiffuseLanes::kLanes, entries.size() - start);
        for (std::size_t k = 0; k < L.size; ++k) L.entry[k] = entries[start + k];
        draw_diffuse_numbers(depth, ws);
        for (std::size_t k = 0; k < L.size; ++k) fill_diffuse_lane(depth, k, ws);
        // The lanes past the last up to the SIMD width: zeros, which make no rays.
        const std::size_t padded = (L.size + width - 1) / width * width;
        for (uint32_t c = 0; c < kern::kDiffuseColumns; ++c)
            std::fill(L.col(c) + L.size, L.col(c) + padded, 0.f);
        kern::shade_diffuse(L.table(), L.size, rules);
        read_diffuse_lanes(ws);
    }
}

}  // namespace foton
