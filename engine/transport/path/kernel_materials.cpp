// Which shading kernel takes each material (kernel_lanes.h's KernelMaterials), decided once
// when the path tracer is made: the material's lobes as the kernels' columns read them.
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

float fresnel_code(const Fresnel& f) {
    return f.kind == FresnelKind::Conductor ? 1.f : f.kind == FresnelKind::Dielectric ? 2.f : 0.f;
}

// A Phong or microfacet lobe for the diffuse kernel's glossy columns; false for any other
// (and for Schlick's Fresnel approximation, which the kernels do not compute).
bool glossy_lobe(const Lobe& l, GlossyMaterial& g) {
    if (l.fresnel.kind == FresnelKind::Schlick) return false;
    if (l.type == LobeType::Phong) {
        g.kind = kern::kGlossPhong;
        g.nu = g.nv = l.exponent;
    } else if (l.type == LobeType::Microfacet) {
        if (l.dist.kind == MicrofacetKind::Beckmann) {
            g.kind = kern::kGlossBeckmann;
            g.nu = g.nv = l.dist.alpha;
        } else if (l.dist.kind == MicrofacetKind::Blinn ||
                   l.dist.kind == MicrofacetKind::AshikhminShirley) {
            g.kind = kern::kGlossCosPower;
            g.nu = l.dist.nu;
            g.nv = l.dist.nv;
        } else {
            g.kind = kern::kGlossGgx;
            g.nu = l.dist.alpha;
            g.nv = l.dist.alpha_y;
        }
    } else {
        return false;
    }
    g.color = l.color;
    g.fresnel = fresnel_code(l.fresnel);
    g.ior = l.fresnel.ior;
    g.eta = l.fresnel.eta;
    g.k = l.fresnel.k;
    return true;
}

// Which kernel shades a material's vertices as shade_vertex would: untextured, not emitting,
// and every lobe Lambertian (their sum is one Lambertian lobe of the summed reflectance); one
// Lambertian or Oren–Nayar lobe with one Phong or microfacet lobe, in either order, or that
// glossy lobe alone; one Oren–Nayar lobe; or one mirror or dielectric lobe.
KernelKind kernel_material(const Material& m, RGB& rho, float& on_a, float& on_b,
                           SpecularMaterial& spec, GlossyMaterial& glossy) {
    if (m.texture >= 0 || !m.emission.is_black() || m.bsdf.empty()) return KernelKind::None;
    const Lobe& first = m.bsdf.lobe(0);
    if (m.bsdf.size() == 1 && m.bsdf.weight(0) > 0.f &&
        first.fresnel.kind != FresnelKind::Schlick &&
        (first.type == LobeType::Mirror || first.type == LobeType::Dielectric)) {
        spec.kind = first.type == LobeType::Mirror ? 1.f : 2.f;
        spec.color = first.color;
        spec.transmit = first.transmit;
        spec.fresnel = fresnel_code(first.fresnel);
        spec.ior = first.fresnel.ior;
        spec.eta = first.fresnel.eta;
        spec.k = first.fresnel.k;
        spec.weight = m.bsdf.weight(0);
        return KernelKind::Specular;
    }
    on_a = 1.f;
    on_b = 0.f;
    // A glossy lobe, alone or with one diffuse lobe.
    for (int gi = 0; gi < m.bsdf.size() && m.bsdf.size() <= 2; ++gi) {
        if (!glossy_lobe(m.bsdf.lobe(gi), glossy)) continue;
        glossy.glossy_weight = m.bsdf.weight(gi);
        glossy.glossy_first = gi == 0 ? 1.f : 0.f;
        rho = RGB{0.f};
        if (m.bsdf.size() == 1) return KernelKind::Diffuse;
        const Lobe& d = m.bsdf.lobe(1 - gi);
        if (d.type != LobeType::Lambert && d.type != LobeType::OrenNayar) break;
        rho = d.color;
        if (d.type == LobeType::OrenNayar) {
            on_a = d.on_a;
            on_b = d.on_b;
        }
        glossy.diffuse_weight = m.bsdf.weight(1 - gi);
        return KernelKind::Diffuse;
    }
    glossy = GlossyMaterial{};
    if (m.bsdf.size() == 1 && first.type == LobeType::OrenNayar) {
        rho = first.color;
        on_a = first.on_a;
        on_b = first.on_b;
        return KernelKind::Diffuse;
    }
    rho = RGB{0.f};
    for (int i = 0; i < m.bsdf.size(); ++i) {
        const Lobe& l = m.bsdf.lobe(i);
        if (l.type != LobeType::Lambert) return KernelKind::None;
        rho += l.color;
    }
    return KernelKind::Diffuse;
}

}  // namespace

KernelMaterials PathIntegrator::kernel_materials() const {
    KernelMaterials d;
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
    d.kernel.assign(ms.size(), KernelKind::None);
    d.rho.assign(ms.size(), RGB{0.f});
    d.on_a.assign(ms.size(), 1.f);
    d.on_b.assign(ms.size(), 0.f);
    d.specular.assign(ms.size(), SpecularMaterial{});
    d.glossy.assign(ms.size(), GlossyMaterial{});
    for (std::size_t k = 0; k < ms.size(); ++k)
        d.kernel[k] =
            kernel_material(ms[k], d.rho[k], d.on_a[k], d.on_b[k], d.specular[k], d.glossy[k]);
    for (const Object& o : ctx_.scene.objects) {
        RGB rho;
        d.object_kernel.push_back(d.kernel[o.material]);
        d.object_lambertian.push_back(d.kernel[o.material] == KernelKind::Diffuse &&
                                      ms[o.material].bsdf.lambert_albedo(rho));
        d.object_group.push_back(uint8_t(d.glossy[o.material].kind));
    }
    return d;
}

}  // namespace foton
