#pragma once
// Real roots of low-degree polynomials, for ray tests against implicit surfaces (the torus'
// quartic). Closed forms for quartics lose most of their digits when a ray grazes the surface
// or starts far away; isolating each root between the critical points (the roots of the
// derivative, found the same way) and refining a sign change by bisection-guarded Newton
// keeps double precision for any degree up to kMaxPolynomialDegree.
namespace foton {

inline constexpr int kMaxPolynomialDegree = 4;

// c[0] + c[1] x + ... + c[n] x^n at x (Horner).
double polynomial_value(const double* c, int n, double x);

// The real roots in [lo, hi] of the polynomial of degree n <= kMaxPolynomialDegree with
// coefficients c[0..n] (low to high), ascending, into roots (room for n); returns how many.
// A root of even multiplicity (a tangent) is found only where the polynomial is exactly zero
// at a critical point: a grazing ray may miss it, as with any floating-point test.
int polynomial_roots(const double* c, int n, double lo, double hi, double* roots);

}  // namespace foton
