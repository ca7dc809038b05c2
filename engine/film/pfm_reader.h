#pragma once
// Portable float maps (.pfm: "PF" colour or "Pf" grey, width height, a scale whose sign is
// the byte order, then rows of 32-bit floats from the bottom up), as pbrt-v4 scenes ship
// their environment maps. Our own reader: the format fits in a few lines, no Debian library
// but OpenImageIO reads it, and every bad header line must be reported as `file:line`.
#include <string>

#include "film.h"

namespace foton {

// The image, top row first, each value times |scale| (pbrt's reading); InputError naming the
// file (and the header line) when it is not a PFM, its size is out of range or the data is
// short.
Film read_pfm(const std::string& path);
Film parse_pfm(const std::string& bytes, const std::string& name);

}  // namespace foton
