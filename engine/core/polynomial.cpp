#include "polynomial.h"

#include <cmath>
#include <utility>

namespace foton {

double polynomial_value(const double* c, int n, double x) {
    double v = c[n];
    for (int i = n - 1; i >= 0; --i) v = v * x + c[i];
    return v;
}

namespace {

double derivative_value(const double* c, int n, double x) {
    double v = n * c[n];
    for (int i = n - 1; i >= 1; --i) v = v * x + i * c[i];
    return v;
}

// The root in [a, b], where f(a) and f(b) have opposite signs: Newton steps while they stay
// inside the bracket, bisection otherwise, until the bracket or a Newton step is down to the
// last bits.
double refine_root(const double* c, int n, double a, double b, double fa) {
    double x = 0.5 * (a + b);
    for (int it = 0; it < 100; ++it) {
        const double fx = polynomial_value(c, n, x);
        if (fx == 0.0) return x;
        if ((fx < 0.0) == (fa < 0.0)) {
            a = x;
            fa = fx;
        } else {
            b = x;
        }
        const double width = b - a;
        if (width <= 4e-16 * (std::fabs(a) + std::fabs(b)) || width == 0.0) break;
        const double dfx = derivative_value(c, n, x);
        double next = dfx != 0.0 ? x - fx / dfx : a;
        if (!(next > a && next < b)) {
            next = 0.5 * (a + b);
        } else if (std::fabs(next - x) <= 1e-15 * (std::fabs(x) + width)) {
            // Newton has converged (from one side the bracket would shrink no further).
            return next;
        }
        x = next;
    }
    return x;
}

int quadratic_roots(double c0, double c1, double c2, double lo, double hi, double* roots) {
    const double disc = c1 * c1 - 4.0 * c2 * c0;
    if (disc < 0.0) return 0;
    // The cancellation-free pair: q = -(c1 + sign(c1) sqrt(disc)) / 2, roots q / c2, c0 / q.
    const double q = -0.5 * (c1 + std::copysign(std::sqrt(disc), c1));
    double r0 = q / c2, r1 = q != 0.0 ? c0 / q : r0;
    if (r0 > r1) std::swap(r0, r1);
    int k = 0;
    if (r0 >= lo && r0 <= hi) roots[k++] = r0;
    if (r1 >= lo && r1 <= hi && (k == 0 || r1 != roots[0])) roots[k++] = r1;
    return k;
}

}  // namespace

int polynomial_roots(const double* c, int n, double lo, double hi, double* roots) {
    while (n > 0 && c[n] == 0.0) --n;
    if (n <= 0 || !(lo <= hi)) return 0;
    if (n == 1) {
        const double x = -c[0] / c[1];
        if (!(x >= lo && x <= hi)) return 0;
        roots[0] = x;
        return 1;
    }
    if (n == 2) return quadratic_roots(c[0], c[1], c[2], lo, hi, roots);
    // The derivative's roots split [lo, hi] into pieces on which the polynomial is monotonic:
    // each holds a root exactly when its ends differ in sign.
    double d[kMaxPolynomialDegree];
    for (int i = 1; i <= n; ++i) d[i - 1] = i * c[i];
    double ends[kMaxPolynomialDegree + 1];
    ends[0] = lo;
    const int critical = polynomial_roots(d, n - 1, lo, hi, ends + 1);
    ends[critical + 1] = hi;
    int k = 0;
    double fa = polynomial_value(c, n, lo);
    if (fa == 0.0) roots[k++] = lo;
    for (int i = 0; i <= critical; ++i) {
        const double a = ends[i], b = ends[i + 1];
        const double fb = polynomial_value(c, n, b);
        if (k == n) break;  // rounding at a double root may show one sign change too many
        if (fb == 0.0) {
            if (k == 0 || roots[k - 1] != b) roots[k++] = b;
        } else if (fa != 0.0 && (fa < 0.0) != (fb < 0.0)) {
            roots[k++] = refine_root(c, n, a, b, fa);
        }
        fa = fb;
    }
    return k;
}

}  // namespace foton
