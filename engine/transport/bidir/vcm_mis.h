#pragma once
// The multiple importance weights of bidirectional path tracing and vertex connection and
// merging, computed recursively along each subpath (Georgiev, "Implementing vertex connection
// and merging", 2012; Veach 1997 ch. 10): every vertex carries three running sums, so the
// weight of any connection or merge is a few multiplications, never a walk over the path.
//
// With p_i the area density of sampling vertex i from the side that reaches it first and
// p_i^rev that of sampling it from the other side, the sums at vertex i of a subpath are
//   dvcm: 1 / p_i,                       (the strategy that joins the two subpaths here)
//   dvc:  the ratios of the connections beyond vertex i, over p_i,
//   dvm:  the ratios of the merges beyond vertex i, over p_i,
// all raised to the heuristic's power (beta 1: balance, 2: power). Merging enters through
// eta = pi r^2 N (N light paths merged with), the ratio of a merge's density to a connection's.
// Cosines are those of the geometric normals: they convert densities between measures, the
// same on both subpaths, so the weights of one path's strategies add up to one.
#include <cmath>
#include <cstdint>

namespace foton {

// What an iteration's weights share.
struct VcmWeights {
    bool connect = true;  // vertex connection (bdpt, vcm)
    bool merge = false;   // vertex merging (bpm, vcm)
    float beta = 1.f;     // heuristic exponent
    float vm_weight = 0;  // mis(eta) when merging: a merge against a connection
    float vc_weight = 0;  // mis(1 / eta) when connecting
    float vm_norm = 0;    // 1 / (pi r^2 N): the merge's density estimate
    // bdpt's debug switch: only strategy (s, t) counts, with full weight (s light vertices,
    // t camera vertices); -1: all strategies, weighted.
    int only_s = -1, only_t = -1;

    float mis(float x) const { return beta == 1.f ? x : beta == 2.f ? x * x : std::pow(x, beta); }
    // The weight of a merge at a vertex, against a connection: none at a medium vertex.
    float merge_at(bool medium_vertex) const { return medium_vertex ? 0.f : vm_weight; }
    // The weight strategy (s, t) gets: `w` from the sums, or the debug switch's 0 or 1.
    float strategy(int s, int t, float w) const {
        if (only_s < 0) return w;
        return s == only_s && t == only_t ? 1.f : 0.f;
    }
};

struct SubpathMis {
    float dvcm = 0.f, dvc = 0.f, dvm = 0.f;

    // The subpath's ray reached its next vertex at distance^2 `d2` (negative: from infinity,
    // no area conversion) with |cos| `cos_in` there.
    void arrive(float d2, float cos_in, const VcmWeights& w) {
        if (d2 >= 0.f) dvcm *= w.mis(d2);
        const float inv = 1.f / w.mis(cos_in);
        dvcm *= inv;
        dvc *= inv;
        dvm *= inv;
    }
    // A delta lobe was sampled (its forward and reverse densities are the same and cancel):
    // no strategy can join the subpaths here.
    void scatter_delta(float cos_out, const VcmWeights& w) {
        dvcm = 0.f;
        dvc *= w.mis(cos_out);
        dvm *= w.mis(cos_out);
    }
    // A non-delta lobe was sampled with solid-angle density `pdf`; `pdf_rev` is the density
    // of the opposite direction at this vertex.
    void scatter(float cos_out, float pdf, float pdf_rev, const VcmWeights& w) {
        const float g = w.mis(cos_out / pdf), rev = w.mis(pdf_rev);
        dvc = g * (dvc * rev + dvcm + w.vm_weight);
        dvm = g * (dvm * rev + dvcm * w.vc_weight + 1.f);
        dvcm = w.mis(1.f / pdf);
    }
    // A medium vertex scattered by its phase function with density pdf (pdf_rev the other
    // way): no cosine, and no merge at this vertex (merging estimates a surface density), so
    // scatter's terms for merging here are left out.
    void scatter_medium(float pdf, float pdf_rev, const VcmWeights& w) {
        const float g = w.mis(1.f / pdf), rev = w.mis(pdf_rev);
        dvc = g * (dvc * rev + dvcm);
        dvm = g * (dvm * rev + dvcm * w.vc_weight);
        dvcm = w.mis(1.f / pdf);
    }
};

}  // namespace foton
