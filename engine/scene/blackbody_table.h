#pragma once
// A medium's glow by temperature (pbrt-v4's temperature grids): the emitted colour of each
// temperature from 100 K, below which nothing glows, to the hottest the medium reaches,
// tabulated once so a lookup costs a linear interpolation, not a spectral integral.
#include <functional>
#include <vector>

#include "engine/core/rgb.h"

namespace foton {

class BlackbodyTable {
  public:
    static constexpr float kCold = 100.f;  // kelvin: pbrt-v4's cut-off
    // `emission(kelvin)` over [kCold, hottest] in `steps` equal steps.
    BlackbodyTable(const std::function<RGB(float)>& emission, float hottest, int steps = 2048);
    RGB at(float kelvin) const;

  private:
    float step_;
    std::vector<RGB> rgb_;
};

}  // namespace foton
