#pragma once
// A glass's refractive index over wavelength, for dispersion in spectral rendering: Cauchy's
// n(lambda) = a + b / lambda^2, fitted to a catalogue's two figures, the index n_d at the
// helium d line (587.56 nm) and the Abbe number V_d = (n_d - 1) / (n_F - n_C) (F 486.13 nm,
// C 656.27 nm). Over the visible range it stays within about 1e-3 of a Sellmeier fit (checked
// for N-BK7 in tests/test_dispersion.cpp). b = 0: no dispersion.
#include <string>

namespace foton {

struct Dispersion {
    float a = 1.5f;
    float b = 0.f;  // nm^2
    bool disperses() const { return b != 0.f; }
    float ior(float lambda_nm) const { return a + b / (lambda_nm * lambda_nm); }
    // The Cauchy fit through n_d with the spread (n_d - 1) / V_d between the F and C lines.
    static Dispersion from_abbe(float nd, float vd);
};

// pbrt-v4's named glasses (glass-BK7, glass-BAF10, glass-FK51A, glass-LASF9, glass-F5: SCHOTT's
// N-BK7, N-BAF10, N-FK51A, N-LASF9 and F5 from their catalogue figures); false for another
// name.
bool named_glass(const std::string& name, Dispersion& out);

}  // namespace foton
