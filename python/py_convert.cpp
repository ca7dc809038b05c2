#include "py_convert.h"

#include <cstring>
#include <string>

namespace foton::py {

pyb::array_t<float> to_array(const Film& film) {
    pyb::array_t<float> a({std::size_t(film.height), std::size_t(film.width), std::size_t(3)});
    std::memcpy(a.mutable_data(), film.pixels.data(), film.pixels.size() * sizeof(RGB));
    return a;
}

pyb::array_t<float> to_array(const AovLayer& layer, int width, int height) {
    std::vector<std::size_t> shape{std::size_t(height), std::size_t(width)};
    if (layer.stride() > 1) shape.push_back(layer.stride());
    pyb::array_t<float> a(shape);
    std::memcpy(a.mutable_data(), layer.values.data(), layer.values.size() * sizeof(float));
    return a;
}

pyb::array_t<uint32_t> to_array(const std::vector<uint32_t>& counts, int width, int height) {
    pyb::array_t<uint32_t> a({std::size_t(height), std::size_t(width)});
    std::memcpy(a.mutable_data(), counts.data(), counts.size() * sizeof(uint32_t));
    return a;
}

Film to_film(const pyb::handle& array, const char* what) {
    const auto a = pyb::array_t<float, pyb::array::c_style | pyb::array::forcecast>::ensure(array);
    if (!a || a.ndim() != 3 || a.shape(2) != 3 || a.shape(0) < 1 || a.shape(1) < 1)
        throw pyb::value_error(std::string(what) +
                               ": expected an image, a (height, width, 3) array of numbers");
    Film f(int(a.shape(1)), int(a.shape(0)));
    std::memcpy(static_cast<void*>(f.pixels.data()), a.data(), f.pixels.size() * sizeof(RGB));
    return f;
}

}  // namespace foton::py
