// Scene's subsurface media: their shared tables, and where the scene first asks for one.
#include "scene.h"

namespace foton {

std::shared_ptr<const BssrdfTable> Scene::subsurface_table(float g, float eta) {
    for (const Subsurface& other : subsurfaces)
        if (other.table->g == g && other.table->eta == eta) return other.table;
    return std::make_shared<const BssrdfTable>(BssrdfTable::compute(g, eta));
}

uint32_t Scene::add_subsurface(const Subsurface& s, const std::string& file, int line) {
    if (subsurface_file.empty()) {
        subsurface_file = file;
        subsurface_line = line;
    }
    subsurfaces.push_back(s);
    return uint32_t(subsurfaces.size() - 1);
}

}  // namespace foton
