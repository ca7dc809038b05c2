#include "blackbody_table.h"

#include <algorithm>
#include <cmath>

namespace foton {

BlackbodyTable::BlackbodyTable(const std::function<RGB(float)>& emission, float hottest, int steps)
    : step_((std::max(hottest, kCold + 1.f) - kCold) / float(steps)) {
    rgb_.resize(std::size_t(steps) + 1);
    for (int i = 0; i <= steps; ++i) rgb_[std::size_t(i)] = emission(kCold + step_ * float(i));
}

RGB BlackbodyTable::at(float kelvin) const {
    if (!(kelvin > kCold)) return RGB{0.f};
    const float x = std::min((kelvin - kCold) / step_, float(rgb_.size() - 1));
    const std::size_t i = std::min(std::size_t(x), rgb_.size() - 2);
    const float f = x - float(i);
    return rgb_[i] * (1.f - f) + rgb_[i + 1] * f;
}

}  // namespace foton
