#include "brute_accel.h"
#include "embree_accel.h"
#include "grid_accel.h"

namespace foton {

std::unique_ptr<Intersector> make_intersector(const Scene& scene, AccelType type) {
    switch (type) {
        case AccelType::Brute: return std::make_unique<BruteAccel>(scene);
        case AccelType::Grid: return std::make_unique<GridAccel>(scene);
        case AccelType::Embree: return std::make_unique<EmbreeAccel>(scene);
    }
    return nullptr;
}

}  // namespace foton
