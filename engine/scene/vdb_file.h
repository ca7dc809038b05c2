#pragma once
// Density grids from OpenVDB (.vdb) and NanoVDB (.nvdb) files: the sparse volumes that smoke,
// clouds and explosions are published in (pbrt-v4's `nanovdb` medium reads the latter).
//
// A float fog-volume grid is read into foton's dense DensityGrid over its active voxels' box,
// padded by one voxel of the background (zero) on every side: VDB values sit at integer index
// coordinates and are interpolated trilinearly towards the background beyond the last active
// voxel, which is what the dense grid does at its padded faces, so a lookup anywhere equals the
// file's trilinear value. The file's index-to-world map and the placement must together be a
// positive scale and a translation per axis (the dense grid is axis-aligned).
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "density_grid.h"
#include "engine/core/math.h"

namespace foton {

// What is wrong with a VDB file or its grid; the caller adds the file and line it came from.
struct VdbError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The names of the grids in the file (either format), in the order its reader lists them.
std::vector<std::string> vdb_grid_names(const std::string& path);

// The float grid `grid_name` of the file as a dense density grid, placed in the world by
// `placement` after the file's own transform. At most `max_samples` dense samples.
std::shared_ptr<const DensityGrid> read_vdb_density(const std::string& path,
                                                    const std::string& grid_name,
                                                    const Affine& placement,
                                                    uint64_t max_samples = uint64_t(1) << 28);

}  // namespace foton
