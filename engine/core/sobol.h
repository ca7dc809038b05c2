#pragma once
// Owen-scrambled Sobol' points (sampler="sobol"): the scalar code and its table kernel live
// with the kernels (kernels/sobol_net.h); the engine names them foton::sobol.
#include "kernels/sobol_net.h"

namespace foton {
namespace sobol = kern::sobol;
}  // namespace foton
