#pragma once
// Catmull-Rom splines through tabulated values on a non-uniform grid: evaluation weights,
// the integral with its running sums, inversion of a monotone spline, and sampling a 1D
// profile picked out of a 2D table by interpolation in its first parameter. The tabulated
// BSSRDF (scene/subsurface/) reads its diffusion profiles through these.
//
// On interval [x_i, x_{i+1}] of width w the spline is the cubic Hermite curve in t in [0, 1]
// through f_i and f_{i+1}, its end slopes (per unit t) the central differences
// (f_{i+1} - f_{i-1}) w / (x_{i+1} - x_{i-1}) and (f_{i+2} - f_i) w / (x_{i+2} - x_i),
// one-sided (f_{i+1} - f_i) at the table's ends.
#include <cstddef>
#include <cstdint>
#include <span>

namespace foton {

// The four weights of f_{offset} .. f_{offset+3} whose sum is the spline at x; false when x
// lies outside the nodes. A weight whose node lies outside the table is zero (and its index
// must not be read).
bool catmull_rom_weights(std::span<const float> nodes, float x, int& offset, float weights[4]);

// The spline's integral over the nodes; cdf[i] = its integral from nodes[0] to nodes[i].
float integrate_catmull_rom(std::span<const float> nodes, std::span<const float> values,
                            std::span<float> cdf);

// The x with spline(x) = y for a spline whose values increase along the nodes (clamped to
// the first and last node outside their values).
float invert_catmull_rom(std::span<const float> nodes, std::span<const float> values, float y);

// Samples x along `nodes2` in proportion to the profile that row-interpolation at `alpha`
// (along `nodes1`) makes of the table `values` (rows of nodes2.size() entries, one per
// nodes1 entry) whose running integrals are `cdf` (integrate_catmull_rom per row). u in
// [0, 1). `value` and `pdf` (optional) get the profile's value at x and its density.
float sample_catmull_rom_2d(std::span<const float> nodes1, std::span<const float> nodes2,
                            std::span<const float> values, std::span<const float> cdf, float alpha,
                            float u, float* value = nullptr, float* pdf = nullptr);

}  // namespace foton
