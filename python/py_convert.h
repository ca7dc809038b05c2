#pragma once
// NumPy arrays to and from foton's images: a film is a (height, width, 3) float32 array, an AOV
// layer (height, width, channels) (a single channel: (height, width)), sample counts
// (height, width) uint32. Arrays are copies: a result outlives nothing it points into.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "engine/film/aov.h"
#include "engine/film/film.h"

namespace foton::py {

namespace pyb = pybind11;

pyb::array_t<float> to_array(const Film& film);
pyb::array_t<float> to_array(const AovLayer& layer, int width, int height);
pyb::array_t<uint32_t> to_array(const std::vector<uint32_t>& counts, int width, int height);
// A (height, width, 3) array of numbers as a film; anything else is a ValueError naming `what`.
Film to_film(const pyb::handle& array, const char* what);

}  // namespace foton::py
