#pragma once
// Randomised Halton points (sampler="halton"): the scalar code and its table kernel live with
// the kernels (kernels/halton_net.h); the engine names them foton::halton.
#include "kernels/halton_net.h"

namespace foton {
namespace halton = kern::halton;
}  // namespace foton
