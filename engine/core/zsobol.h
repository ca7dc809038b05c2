#pragma once
// Sobol' points in Z-order over the image (sampler="zsobol"): the scalar code and its table
// kernel live with the kernels (kernels/zsobol_net.h); the engine names them foton::zsobol.
#include "kernels/zsobol_net.h"

namespace foton {
namespace zsobol = kern::zsobol;
}  // namespace foton
