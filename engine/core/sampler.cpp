#include "sampler.h"

#include <cmath>

#include "halton.h"
#include "rng.h"
#include "sobol.h"

namespace foton {

const EnumTable<SamplerKind>& sampler_names() {
    static const EnumTable<SamplerKind> t{{{"regular", SamplerKind::Regular},
                                           {"random", SamplerKind::Random},
                                           {"jittered", SamplerKind::Jittered},
                                           {"hammersley", SamplerKind::Hammersley},
                                           {"sobol", SamplerKind::Sobol},
                                           {"halton", SamplerKind::Halton},
                                           {"zsobol", SamplerKind::ZSobol}}};
    return t;
}

std::optional<SamplerKind> parse_sampler(std::string_view name) {
    SamplerKind k;
    if (!sampler_names().parse(name, k)) return std::nullopt;
    return k;
}

const char* sampler_name(SamplerKind kind) {
    return sampler_names().name(kind);
}

float radical_inverse2(uint32_t i) {
    i = (i << 16) | (i >> 16);
    i = ((i & 0x00ff00ffu) << 8) | ((i & 0xff00ff00u) >> 8);
    i = ((i & 0x0f0f0f0fu) << 4) | ((i & 0xf0f0f0f0u) >> 4);
    i = ((i & 0x33333333u) << 2) | ((i & 0xccccccccu) >> 2);
    i = ((i & 0x55555555u) << 1) | ((i & 0xaaaaaaaau) >> 1);
    return float(i >> 8) * (1.f / 16777216.f);
}

void stratum_grid(uint32_t n, uint32_t& cols, uint32_t& rows) {
    rows = uint32_t(std::sqrt(double(n)));
    while (rows > 1 && n % rows != 0) --rows;
    if (rows == 0) rows = 1;
    cols = n / rows;
}

Point2 sample_pattern(SamplerKind kind, uint32_t i, uint32_t n, uint64_t seed, uint64_t key) {
    switch (kind) {
        case SamplerKind::Random:
            return {rng::uniform(seed, key, i, 0), rng::uniform(seed, key, i, 1)};
        case SamplerKind::Regular:
        case SamplerKind::Jittered: {
            uint32_t cols, rows;
            stratum_grid(n, cols, rows);
            const uint32_t cx = i % cols, cy = i / cols;
            float jx = 0.5f, jy = 0.5f;
            if (kind == SamplerKind::Jittered) {
                jx = rng::uniform(seed, key, i, 0);
                jy = rng::uniform(seed, key, i, 1);
            }
            return {(float(cx) + jx) / float(cols), (float(cy) + jy) / float(rows)};
        }
        case SamplerKind::Sobol:
        case SamplerKind::ZSobol: {
            Point2 p;
            sobol::sample2(i, n, seed, key, 0, p.x, p.y);
            return p;
        }
        case SamplerKind::Halton:
            return {halton::sample(i, seed, key, 0), halton::sample(i, seed, key, 1)};
        case SamplerKind::Hammersley: {
            // Centred Hammersley: shifted by half a stratum so that n = 1 is the pixel centre.
            const float x = (float(i) + 0.5f) / float(n);
            float y = radical_inverse2(i) + 0.5f / float(n);
            if (y >= 1.f) y -= 1.f;
            return {x, y};
        }
    }
    return {0.5f, 0.5f};
}

}  // namespace foton
