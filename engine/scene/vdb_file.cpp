#include "vdb_file.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iostream>  // NanoVDB's GridValidator.h uses std::cerr without including it
#include <mutex>

// NanoVDB's reader takes compressed files only if told it may.
#define NANOVDB_USE_ZIP 1
#define NANOVDB_USE_BLOSC 1
#include <nanovdb/util/GridValidator.h>
#include <nanovdb/util/IO.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

namespace foton {
namespace {

enum class Format { OpenVdb, NanoVdb };

Format format_of(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw VdbError("cannot be opened");
    unsigned char magic[8] = {};
    in.read(reinterpret_cast<char*>(magic), 8);
    if (in.gcount() < 8) throw VdbError("is too short to be a VDB file");
    if (std::memcmp(magic, "NanoVDB", 7) == 0) return Format::NanoVdb;
    if (magic[0] == 0x20 && magic[1] == 0x42 && magic[2] == 0x44 && magic[3] == 0x56)
        return Format::OpenVdb;
    throw VdbError("is neither an OpenVDB nor a NanoVDB file (its first bytes say neither)");
}

void init_openvdb() {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
}

// What both formats give: the active voxels' inclusive index box, the index-to-world map per
// axis (world = scale * index + offset), the background, and the values by index.
struct SparseGrid {
    int lo[3], hi[3];
    double scale[3], offset[3];
    float background = 0.f;
};

// The map from index to world must leave each axis on itself, stretched by a positive factor.
template <typename ToWorld>
void read_map(ToWorld to_world, SparseGrid& g) {
    const auto o = to_world(0.0, 0.0, 0.0);
    for (int a = 0; a < 3; ++a) {
        double unit[3] = {0, 0, 0};
        unit[a] = 1.0;
        const auto e = to_world(unit[0], unit[1], unit[2]);
        for (int b = 0; b < 3; ++b) {
            const double d = e[b] - o[b];
            if (b == a && !(d > 0.0))
                throw VdbError("the grid's transform mirrors or collapses an axis");
            if (b != a && std::fabs(d) > 1e-9 * std::fabs(e[a] - o[a]))
                throw VdbError(
                    "the grid's transform rotates or shears it (foton's grids are axis-aligned)");
        }
        g.scale[a] = e[a] - o[a];
        g.offset[a] = o[a];
    }
}

// Densifies over the active box padded by one voxel; `make_lookup()` gives each worker its own
// accessor (VDB accessors cache the path to the last voxel and are not shared).
template <typename MakeLookup>
std::shared_ptr<const DensityGrid> densify(const SparseGrid& g, const Affine& placement,
                                           uint64_t max_samples, MakeLookup make_lookup) {
    if (std::fabs(g.background) > 0.f)
        throw VdbError("the grid's background is " + std::to_string(g.background) +
                       "; a density grid's must be 0 (a fog volume)");
    int n[3];
    uint64_t count = 1;
    for (int a = 0; a < 3; ++a) {
        n[a] = g.hi[a] - g.lo[a] + 3;
        count *= uint64_t(n[a]);
    }
    if (count > max_samples)
        throw VdbError("the active voxels span " + std::to_string(n[0] - 2) + " x " +
                       std::to_string(n[1] - 2) + " x " + std::to_string(n[2] - 2) +
                       " voxels; foton reads at most " + std::to_string(max_samples) +
                       " as a dense grid");
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if ((i != j && placement.m[i][j] != 0.f) || (i == j && !(placement.m[i][i] > 0.f)))
                throw VdbError(
                    "the grid's placement must be positive scales and translations only");
    std::vector<float> values(count);
    std::string problem;
    std::mutex problem_mutex;
    tbb::parallel_for(0, n[2], [&](int z) {
        auto value = make_lookup();
        for (int y = 0; y < n[1]; ++y)
            for (int x = 0; x < n[0]; ++x) {
                const int i = g.lo[0] - 1 + x, j = g.lo[1] - 1 + y, k = g.lo[2] - 1 + z;
                const float v = value(i, j, k);
                if (!(v >= 0.f && v < 1e12f)) {
                    const std::lock_guard<std::mutex> lock(problem_mutex);
                    problem = "the voxel at (" + std::to_string(i) + ", " + std::to_string(j) +
                              ", " + std::to_string(k) + ") is " + std::to_string(v) +
                              " (densities are finite, non-negative and below 1e12)";
                }
                values[(std::size_t(z) * std::size_t(n[1]) + std::size_t(y)) * std::size_t(n[0]) +
                       std::size_t(x)] = v;
            }
    });
    if (!problem.empty()) throw VdbError(problem);
    // Sample x sits at index lo - 1 + x: the dense grid's cells are centred on the voxels.
    Vec3 lo, hi;
    for (int a = 0; a < 3; ++a) {
        lo[a] = float(g.scale[a] * (g.lo[a] - 1.5) + g.offset[a]);
        hi[a] = float(g.scale[a] * (g.hi[a] + 1.5) + g.offset[a]);
    }
    Bounds3 box;
    box.extend(placement.point(lo));
    box.extend(placement.point(hi));
    return std::make_shared<const DensityGrid>(n[0], n[1], n[2], std::move(values), box);
}

std::shared_ptr<const DensityGrid> read_openvdb(const std::string& path, const std::string& name,
                                                const Affine& placement, uint64_t max_samples) {
    init_openvdb();
    openvdb::io::File file(path);
    file.open(false);
    if (!file.hasGrid(name)) throw VdbError("has no grid named '" + name + "'");
    const openvdb::GridBase::Ptr base = file.readGrid(name);
    file.close();
    const openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    if (!grid) throw VdbError("grid '" + name + "' holds " + base->valueType() + ", not float");
    if (grid->getGridClass() == openvdb::GRID_LEVEL_SET)
        throw VdbError("grid '" + name + "' is a level set, not a fog volume");
    const openvdb::CoordBBox bb = grid->evalActiveVoxelBoundingBox();
    if (bb.empty()) throw VdbError("grid '" + name + "' has no active voxels");
    SparseGrid g;
    for (int a = 0; a < 3; ++a) {
        g.lo[a] = bb.min()[a];
        g.hi[a] = bb.max()[a];
    }
    g.background = grid->background();
    if (!grid->transform().isLinear()) throw VdbError("the grid's transform is not linear");
    read_map(
        [&](double x, double y, double z) {
            const openvdb::Vec3d w = grid->transform().indexToWorld(openvdb::Vec3d(x, y, z));
            return std::array<double, 3>{w[0], w[1], w[2]};
        },
        g);
    return densify(g, placement, max_samples, [&] {
        return [acc = grid->getConstAccessor()](int i, int j, int k) {
            return acc.getValue(openvdb::Coord(i, j, k));
        };
    });
}

std::shared_ptr<const DensityGrid> read_nanovdb(const std::string& path, const std::string& name,
                                                const Affine& placement, uint64_t max_samples) {
    nanovdb::GridHandle<> handle = nanovdb::io::readGrid(path, name);
    if (!handle) throw VdbError("has no grid named '" + name + "'");
    const nanovdb::FloatGrid* grid = handle.grid<float>();
    if (!grid)
        throw VdbError("grid '" + name + "' holds " +
                       std::string(nanovdb::toStr(handle.gridMetaData()->gridType())) +
                       ", not float");
    // The reader trusts the file's offsets; the validator checks them and the checksum first.
    if (!nanovdb::isValid(*grid, true, false))
        throw VdbError("grid '" + name + "' fails NanoVDB's validation (a damaged file?)");
    if (grid->gridClass() == nanovdb::GridClass::LevelSet)
        throw VdbError("grid '" + name + "' is a level set, not a fog volume");
    const nanovdb::CoordBBox bb = grid->indexBBox();
    if (grid->activeVoxelCount() == 0 || bb.empty())
        throw VdbError("grid '" + name + "' has no active voxels");
    SparseGrid g;
    for (int a = 0; a < 3; ++a) {
        g.lo[a] = bb.min()[a];
        g.hi[a] = bb.max()[a];
    }
    g.background = grid->tree().background();
    read_map(
        [&](double x, double y, double z) {
            const nanovdb::Vec3d w = grid->indexToWorld(nanovdb::Vec3d(x, y, z));
            return std::array<double, 3>{w[0], w[1], w[2]};
        },
        g);
    return densify(g, placement, max_samples, [&] {
        return [acc = grid->getAccessor()](int i, int j, int k) mutable {
            return acc.getValue(nanovdb::Coord(i, j, k));
        };
    });
}

}  // namespace

std::vector<std::string> vdb_grid_names(const std::string& path) {
    std::vector<std::string> names;
    try {
        if (format_of(path) == Format::NanoVdb) {
            for (const auto& meta : nanovdb::io::readGridMetaData(path))
                names.push_back(meta.gridName);
        } else {
            init_openvdb();
            openvdb::io::File file(path);
            file.open(false);
            for (auto it = file.beginName(); it != file.endName(); ++it)
                names.push_back(it.gridName());
            file.close();
        }
    } catch (const VdbError&) {
        throw;
    } catch (const std::exception& e) {
        throw VdbError(e.what());
    }
    return names;
}

std::shared_ptr<const DensityGrid> read_vdb_density(const std::string& path,
                                                    const std::string& grid_name,
                                                    const Affine& placement, uint64_t max_samples) {
    try {
        return format_of(path) == Format::NanoVdb
                   ? read_nanovdb(path, grid_name, placement, max_samples)
                   : read_openvdb(path, grid_name, placement, max_samples);
    } catch (const VdbError&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw VdbError("is too large to read (out of memory)");
    } catch (const std::exception& e) {
        // OpenVDB's and NanoVDB's own exceptions say what they found wrong.
        throw VdbError(e.what());
    }
}

}  // namespace foton
