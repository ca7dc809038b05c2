#include "math.h"

namespace foton {

float Affine::determinant() const {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

Vec3 Affine::normal(const Vec3& n) const {
    // Cofactor matrix = det * inverse transpose; the scale drops out after normalisation.
    const float c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
    const float c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
    const float c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
    const float c10 = m[0][2] * m[2][1] - m[0][1] * m[2][2];
    const float c11 = m[0][0] * m[2][2] - m[0][2] * m[2][0];
    const float c12 = m[0][1] * m[2][0] - m[0][0] * m[2][1];
    const float c20 = m[0][1] * m[1][2] - m[0][2] * m[1][1];
    const float c21 = m[0][2] * m[1][0] - m[0][0] * m[1][2];
    const float c22 = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    // Row i of the cofactor matrix times n (its transpose, the adjugate, would apply the
    // inverse: a rotation's normals turned the other way).
    Vec3 r{c00 * n.x + c01 * n.y + c02 * n.z, c10 * n.x + c11 * n.y + c12 * n.z,
           c20 * n.x + c21 * n.y + c22 * n.z};
    if (determinant() < 0.f) r = -r;
    return normalize(r);
}

Affine Affine::inverse() const {
    // In double: cameras far from the origin (pbrt's LookAt at 800 units) keep their basis.
    double a[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) a[i][j] = m[i][j];
    const double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                       a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                       a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    double inv[3][3];
    inv[0][0] = (a[1][1] * a[2][2] - a[1][2] * a[2][1]) / det;
    inv[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) / det;
    inv[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) / det;
    inv[1][0] = (a[1][2] * a[2][0] - a[1][0] * a[2][2]) / det;
    inv[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) / det;
    inv[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) / det;
    inv[2][0] = (a[1][0] * a[2][1] - a[1][1] * a[2][0]) / det;
    inv[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) / det;
    inv[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) / det;
    Affine r;
    for (int i = 0; i < 3; ++i) {
        double t = 0.0;
        for (int j = 0; j < 3; ++j) {
            r.m[i][j] = float(inv[i][j]);
            t -= inv[i][j] * double(m[j][3]);
        }
        r.m[i][3] = float(t);
    }
    return r;
}

Affine Affine::translate(const Vec3& t) {
    Affine a;
    a.m[0][3] = t.x;
    a.m[1][3] = t.y;
    a.m[2][3] = t.z;
    return a;
}

Affine Affine::scale(const Vec3& s) {
    Affine a;
    a.m[0][0] = s.x;
    a.m[1][1] = s.y;
    a.m[2][2] = s.z;
    return a;
}

Affine Affine::rotate(const Vec3& axis_in, float degrees) {
    const Vec3 k = normalize(axis_in);
    const float th = degrees * kPi / 180.f;
    const float c = std::cos(th), s = std::sin(th), t = 1.f - c;
    Affine a;
    a.m[0][0] = t * k.x * k.x + c;
    a.m[0][1] = t * k.x * k.y - s * k.z;
    a.m[0][2] = t * k.x * k.z + s * k.y;
    a.m[1][0] = t * k.x * k.y + s * k.z;
    a.m[1][1] = t * k.y * k.y + c;
    a.m[1][2] = t * k.y * k.z - s * k.x;
    a.m[2][0] = t * k.x * k.z - s * k.y;
    a.m[2][1] = t * k.y * k.z + s * k.x;
    a.m[2][2] = t * k.z * k.z + c;
    return a;
}

Affine Affine::operator*(const Affine& f) const {
    Affine r;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 4; ++j) {
            float v = 0.f;
            for (int k = 0; k < 3; ++k) v += m[i][k] * f.m[k][j];
            if (j == 3) v += m[i][3];
            r.m[i][j] = v;
        }
    }
    return r;
}

bool Affine::is_identity() const {
    const Affine id;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j)
            if (m[i][j] != id.m[i][j]) return false;
    return true;
}

}  // namespace foton
