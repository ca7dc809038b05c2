#pragma once
// The CIE's standard tables foton's spectral mode integrates against: the CIE 1931 2-degree
// colour matching functions and illuminant D65's relative spectral power, both tabulated every
// 5 nm from 360 to 830 nm. They are data, not code: the build reads them from Debian's
// colord-data package (/usr/share/colord) into cie_tables.cpp (engine/CMakeLists.txt).
#include <cstddef>

namespace foton::cie {

inline constexpr float kLambdaMin = 360.f, kLambdaMax = 830.f, kStep = 5.f;
inline constexpr std::size_t kSamples = 95;  // (830 - 360) / 5 + 1

extern const float kX[kSamples], kY[kSamples], kZ[kSamples];  // x-bar, y-bar, z-bar
extern const float kD65[kSamples];                            // relative, 1 at 560 nm

}  // namespace foton::cie
