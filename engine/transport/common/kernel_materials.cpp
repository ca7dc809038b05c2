// Which shading kernel takes each material (kernel_materials.h), decided once when an
// integrator is made: the material's lobes as the kernels' columns read them.
#include "kernel_materials.h"

namespace foton {

namespace {

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
    if (m.varies() || m.needs_tangent() || !m.emission.is_black() || m.bsdf.empty())
        return KernelKind::None;
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

KernelMaterials kernel_materials(const Scene& scene) {
    KernelMaterials d;
    const std::vector<Material>& ms = scene.materials;
    d.kernel.assign(ms.size(), KernelKind::None);
    d.rho.assign(ms.size(), RGB{0.f});
    d.on_a.assign(ms.size(), 1.f);
    d.on_b.assign(ms.size(), 0.f);
    d.specular.assign(ms.size(), SpecularMaterial{});
    d.glossy.assign(ms.size(), GlossyMaterial{});
    for (std::size_t k = 0; k < ms.size(); ++k)
        d.kernel[k] =
            kernel_material(ms[k], d.rho[k], d.on_a[k], d.on_b[k], d.specular[k], d.glossy[k]);
    for (const Object& o : scene.objects) {
        RGB rho;
        d.object_kernel.push_back(d.kernel[o.material]);
        d.object_lambertian.push_back(d.kernel[o.material] == KernelKind::Diffuse &&
                                      ms[o.material].bsdf.lambert_albedo(rho));
        d.object_group.push_back(uint8_t(d.glossy[o.material].kind));
    }
    return d;
}

void put_diffuse_material(KernelLanes& L, std::size_t lane, const KernelMaterials& km,
                          uint32_t material) {
    L.put3(kern::kDvRhoR, lane, km.rho[material]);
    L.col(kern::kDvOnA)[lane] = km.on_a[material];
    L.col(kern::kDvOnB)[lane] = km.on_b[material];
    const GlossyMaterial& g = km.glossy[material];
    L.col(kern::kDvGlossKind)[lane] = g.kind;
    if (g.kind == 0.f) return;
    L.put3(kern::kDvGlossR, lane, g.color);
    L.col(kern::kDvGlossNu)[lane] = g.nu;
    L.col(kern::kDvGlossNv)[lane] = g.nv;
    L.col(kern::kDvDiffuseWeight)[lane] = g.diffuse_weight;
    L.col(kern::kDvGlossWeight)[lane] = g.glossy_weight;
    L.col(kern::kDvGlossFirst)[lane] = g.glossy_first;
    L.col(kern::kDvFresnel)[lane] = g.fresnel;
    L.col(kern::kDvIor)[lane] = g.ior;
    L.put3(kern::kDvEtaR, lane, g.eta);
    L.put3(kern::kDvKR, lane, g.k);
}

}  // namespace foton
