#pragma once
// Free flights through a majorant grid: the piecewise-constant upper bound of a grid medium's
// extinction (engine/scene/density_grid.h builds it, per unit length). A flight starts at t
// along o + t d with an optical depth tau to spend (tau = -ln(1 - u) for delta or ratio
// tracking's next tentative collision); the march walks the cells with the 3D DDA of
// grid_dda.h, spending each cell's majorant times its length, and stops where tau runs out (a
// tentative collision, at the exact point inside the cell) or at t_end.
//
// march_majorant runs W flights at a time, each lane at its own cell; march_majorant_scalar is
// its twin, one flight at a time. Both do the same IEEE operations in the same order, so their
// results agree bit for bit.
#include <cstddef>
#include <cstdint>

namespace foton::kern {

struct MajorantGrid {
    float lo[3], cell[3], inv_cell[3];
    int res[3];
    const float* majorant;  // res[0] * res[1] * res[2] cells, x fastest
    float scale = 1.f;      // times each cell's value: the majorant per unit length
};

// Structure of arrays, `count` flights. In: origin, direction, t (start), t_end, tau. Out: t
// (the tentative collision, or t_end), collided (1 or 0), majorant (the collision cell's).
struct MarchFlights {
    const float *ox, *oy, *oz, *dx, *dy, *dz;
    const float* t_end;
    const float* tau;
    float* t;
    float* majorant;
    uint8_t* collided;
};

void march_majorant(const MajorantGrid& g, const MarchFlights& f, std::size_t count);
void march_majorant_scalar(const MajorantGrid& g, const MarchFlights& f, std::size_t count);

}  // namespace foton::kern
