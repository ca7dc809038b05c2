#pragma once
// A linear-radiance RGB image, row-major, pixel (0, 0) at the top left.
#include <vector>

#include "engine/core/rgb.h"

namespace foton {

struct Film {
    int width = 0, height = 0;
    std::vector<RGB> pixels;

    Film() = default;
    Film(int w, int h) : width(w), height(h), pixels(std::size_t(w) * std::size_t(h)) {}
    RGB& at(int x, int y) { return pixels[std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
    const RGB& at(int x, int y) const {
        return pixels[std::size_t(y) * std::size_t(width) + std::size_t(x)];
    }
};

}  // namespace foton
