#pragma once
// How next event estimation chooses the light it samples (LightSet::pick, light_pick.cpp).
#include <cstdint>

namespace foton {

enum class LightSelection : uint8_t {
    Power,    // in proportion to power, wherever the receiver is
    Uniform,  // every emitter alike
    // By importance at the receiver (light_bvh.h): each triangle of an emissive mesh is a
    // light of its own, chosen by its distance, orientation and power; lights at infinity
    // share one choice with the tree.
    Bvh,
};

}  // namespace foton
