#include "noise.h"

#include <cmath>
#include <cstdint>

namespace foton {

namespace {

// Perlin's permutation of 0..255 (his reference implementation's table).
constexpr uint8_t kPerm[256] = {
    151, 160, 137, 91,  90,  15,  131, 13,  201, 95,  96,  53,  194, 233, 7,   225, 140, 36,  103,
    30,  69,  142, 8,   99,  37,  240, 21,  10,  23,  190, 6,   148, 247, 120, 234, 75,  0,   26,
    197, 62,  94,  252, 219, 203, 117, 35,  11,  32,  57,  177, 33,  88,  237, 149, 56,  87,  174,
    20,  125, 136, 171, 168, 68,  175, 74,  165, 71,  134, 139, 48,  27,  166, 77,  146, 158, 231,
    83,  111, 229, 122, 60,  211, 133, 230, 220, 105, 92,  41,  55,  46,  245, 40,  244, 102, 143,
    54,  65,  25,  63,  161, 1,   216, 80,  73,  209, 76,  132, 187, 208, 89,  18,  169, 200, 196,
    135, 130, 116, 188, 159, 86,  164, 100, 109, 198, 173, 186, 3,   64,  52,  217, 226, 250, 124,
    123, 5,   202, 38,  147, 118, 126, 255, 82,  85,  212, 207, 206, 59,  227, 47,  16,  58,  17,
    182, 189, 28,  42,  223, 183, 170, 213, 119, 248, 152, 2,   44,  154, 163, 70,  221, 153, 101,
    155, 167, 43,  172, 9,   129, 22,  39,  253, 19,  98,  108, 110, 79,  113, 224, 232, 178, 185,
    112, 104, 218, 246, 97,  228, 251, 34,  242, 193, 238, 210, 144, 12,  191, 179, 162, 241, 81,
    51,  145, 235, 249, 14,  239, 107, 49,  192, 214, 31,  181, 199, 106, 157, 184, 84,  204, 176,
    115, 121, 50,  45,  127, 4,   150, 254, 138, 236, 205, 93,  222, 114, 67,  29,  24,  72,  243,
    141, 128, 195, 78,  66,  215, 61,  156, 180};

int noise_perm(int i) {
    return kPerm[i & 255];
}

// The dot product of one of twelve edge gradients (chosen by h) with (x, y, z).
float noise_gradient(int h, float x, float y, float z) {
    h &= 15;
    const float u = h < 8 ? x : y;
    const float v = h < 4 ? y : (h == 12 || h == 14 ? x : z);
    return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
}

float noise_fade(float t) {
    return t * t * t * (t * (t * 6.f - 15.f) + 10.f);
}

float noise_lerp(float t, float a, float b) {
    return a + t * (b - a);
}

// The lattice cell of a coordinate (its low 8 bits: the table repeats every 256) and the
// offset in it, in double so that a huge coordinate does not overflow the int.
int lattice_cell(float v, float& frac) {
    const double f = std::floor(double(v));
    frac = float(double(v) - f);
    return int(std::fmod(f, 256.0) + 256.0) & 255;
}

}  // namespace

float perlin_noise(const Vec3& p) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return 0.f;
    float x, y, z;
    const int X = lattice_cell(p.x, x), Y = lattice_cell(p.y, y), Z = lattice_cell(p.z, z);
    const float u = noise_fade(x), v = noise_fade(y), w = noise_fade(z);
    const int a = noise_perm(X) + Y, aa = noise_perm(a) + Z, ab = noise_perm(a + 1) + Z;
    const int b = noise_perm(X + 1) + Y, ba = noise_perm(b) + Z, bb = noise_perm(b + 1) + Z;
    return noise_lerp(
        w,
        noise_lerp(v,
                   noise_lerp(u, noise_gradient(noise_perm(aa), x, y, z),
                              noise_gradient(noise_perm(ba), x - 1, y, z)),
                   noise_lerp(u, noise_gradient(noise_perm(ab), x, y - 1, z),
                              noise_gradient(noise_perm(bb), x - 1, y - 1, z))),
        noise_lerp(v,
                   noise_lerp(u, noise_gradient(noise_perm(aa + 1), x, y, z - 1),
                              noise_gradient(noise_perm(ba + 1), x - 1, y, z - 1)),
                   noise_lerp(u, noise_gradient(noise_perm(ab + 1), x, y - 1, z - 1),
                              noise_gradient(noise_perm(bb + 1), x - 1, y - 1, z - 1))));
}

float fbm(const Vec3& p, float omega, int octaves) {
    float sum = 0.f, o = 1.f, lambda = 1.f;
    for (int i = 0; i < octaves; ++i) {
        sum += o * perlin_noise(p * lambda);
        lambda *= 1.99f;
        o *= omega;
    }
    return sum;
}

float turbulence(const Vec3& p, float omega, int octaves) {
    float sum = 0.f, o = 1.f, lambda = 1.f;
    for (int i = 0; i < octaves; ++i) {
        sum += o * std::fabs(perlin_noise(p * lambda));
        lambda *= 1.99f;
        o *= omega;
    }
    return sum + 0.2f * o;
}

}  // namespace foton
