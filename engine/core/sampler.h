#pragma once
// 2D sample patterns of the first thesis: regular, random, jittered and Hammersley, and
// Owen-scrambled Sobol' (sobol.h), randomised Halton (halton.h) and Sobol' in Z-order over the
// image (zsobol.h), which the path tracer also draws its paths' dimensions from. A pattern of n
// points over the unit square; point i is a pure function of (kind, i, n, seed, key), so any subset
// of a pixel's samples can be generated independently.
#include <cstdint>
#include <optional>
#include <string_view>

#include "params.h"

namespace foton {

enum class SamplerKind { Regular, Random, Jittered, Hammersley, Sobol, Halton, ZSobol };

struct Point2 {
    float x = 0.f, y = 0.f;
};

const EnumTable<SamplerKind>& sampler_names();
std::optional<SamplerKind> parse_sampler(std::string_view name);
const char* sampler_name(SamplerKind kind);

// Van der Corput radical inverse in base 2.
float radical_inverse2(uint32_t i);

// Factorises n = rows * cols with rows the largest divisor of n not above sqrt(n), so the
// strata of regular and jittered patterns are as square as n allows (a prime n gives strips).
void stratum_grid(uint32_t n, uint32_t& cols, uint32_t& rows);

// Point i of an n-point pattern. `key` decorrelates patterns (pixel index, light, ...).
// ZSobol orders pixels, so a pattern with no pixel behind it (an area light's samples) draws
// the padded Sobol' points; a pixel's film position comes from pixel_sample
// (transport/common/camera_integrator.h), which knows the pixel.
Point2 sample_pattern(SamplerKind kind, uint32_t i, uint32_t n, uint64_t seed, uint64_t key);

}  // namespace foton
