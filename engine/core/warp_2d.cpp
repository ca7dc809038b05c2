#include "warp_2d.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace foton {

namespace {

// The largest i in [0, n - 2] with below(i) true, for a `below` that is true up to some index
// and false after it (0 when it is false everywhere).
template <class Below>
uint32_t find_interval(uint32_t n, Below&& below) {
    uint32_t lo = 0, hi = n - 1;  // below(lo) assumed; the answer is in [lo, hi)
    while (hi - lo > 1) {
        const uint32_t mid = lo + (hi - lo) / 2;
        if (below(mid))
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

// The position t in [0, 1] of a linear density a (1 - t) + b t whose mass up to t is m
// (a t + (b - a) t^2 / 2 = m).
float solve_linear_mass(float a, float b, float m) {
    if (std::fabs(a - b) < 1e-4f * (a + b)) return 2.f * m / (a + b);
    return (a - std::sqrt(std::max(0.f, a * a - 2.f * m * (a - b)))) / (a - b);
}

}  // namespace

Warp2D::Warp2D(const float* data, int width, int height, std::vector<std::vector<float>> params,
               bool normalize, bool build_cdf)
    : width_(width), height_(height), param_values_(std::move(params)) {
    if (width < 2 || height < 2 || param_values_.size() > 4)
        throw std::invalid_argument("Warp2D: a grid of at least 2 x 2 nodes, at most 4 parameters");
    for (const std::vector<float>& v : param_values_)
        if (v.empty()) throw std::invalid_argument("Warp2D: a parameter without nodes");
    uint32_t slices = 1;
    param_stride_.assign(param_values_.size(), 0);
    for (int d = int(param_values_.size()) - 1; d >= 0; --d) {
        const std::size_t n = param_values_[std::size_t(d)].size();
        param_stride_[std::size_t(d)] = n > 1 ? slices : 0;
        slices *= uint32_t(n);
    }
    const std::size_t n = std::size_t(width) * std::size_t(height);
    data_.resize(slices * n);
    const float cells = float(width - 1) * float(height - 1);
    if (build_cdf) {
        marginal_cdf_.resize(slices * std::size_t(height));
        conditional_cdf_.resize(slices * n);
    }
    for (uint32_t s = 0; s < slices; ++s) {
        const float* in = data + s * n;
        float* out = data_.data() + s * n;
        float scale = 1.f / cells;  // eval() then returns the data as given
        if (build_cdf) {
            // Per node row, the trapezoid sums along x; then over rows, the rows' totals.
            float* cond = conditional_cdf_.data() + s * n;
            float* marg = marginal_cdf_.data() + s * std::size_t(height);
            for (int y = 0; y < height; ++y) {
                const std::size_t row = std::size_t(y) * std::size_t(width);
                double sum = 0.0;
                cond[row] = 0.f;
                for (int x = 0; x + 1 < width; ++x) {
                    sum += 0.5 * (double(in[row + std::size_t(x)]) + in[row + std::size_t(x) + 1]);
                    cond[row + std::size_t(x) + 1] = float(sum);
                }
            }
            double sum = 0.0;
            marg[0] = 0.f;
            for (int y = 0; y + 1 < height; ++y) {
                sum += 0.5 * (double(cond[std::size_t(y + 1) * std::size_t(width) - 1]) +
                              cond[std::size_t(y + 2) * std::size_t(width) - 1]);
                marg[y + 1] = float(sum);
            }
            if (!(marg[height - 1] > 0.f))
                throw std::invalid_argument("Warp2D: a grid without mass");
            scale = 1.f / marg[height - 1];
            for (std::size_t i = 0; i < n; ++i) cond[i] *= scale;
            for (int y = 0; y < height; ++y) marg[y] *= scale;
        } else if (normalize) {
            double sum = 0.0;
            for (int y = 0; y + 1 < height; ++y)
                for (int x = 0; x + 1 < width; ++x) {
                    const std::size_t i = std::size_t(y) * std::size_t(width) + std::size_t(x);
                    sum += 0.25 * (double(in[i]) + in[i + 1] + in[i + std::size_t(width)] +
                                   in[i + std::size_t(width) + 1]);
                }
            scale = float(1.0 / sum);
        }
        for (std::size_t i = 0; i < n; ++i) out[i] = in[i] * scale;
    }
}

Warp2D::Corners Warp2D::corners(const float* param) const {
    Corners c;
    for (std::size_t d = 0; d < param_values_.size(); ++d) {
        const std::vector<float>& v = param_values_[d];
        if (v.size() == 1) {
            c.weight[2 * d] = 1.f;
            c.weight[2 * d + 1] = 0.f;
            continue;
        }
        const uint32_t i =
            find_interval(uint32_t(v.size()), [&](uint32_t k) { return v[k] <= param[d]; });
        const float t = std::clamp((param[d] - v[i]) / (v[i + 1] - v[i]), 0.f, 1.f);
        c.weight[2 * d] = 1.f - t;
        c.weight[2 * d + 1] = t;
        c.slice += param_stride_[d] * i;
    }
    return c;
}

float Warp2D::lookup(const std::vector<float>& values, uint32_t offset, uint32_t stride,
                     const Corners& c) const {
    const std::size_t dims = param_values_.size();
    float sum = 0.f;
    for (uint32_t corner = 0; corner < (1u << dims); ++corner) {
        float w = 1.f;
        uint32_t at = offset;
        for (std::size_t d = 0; d < dims; ++d) {
            const uint32_t bit = (corner >> d) & 1u;
            w *= c.weight[2 * d + bit];
            at += bit * param_stride_[d] * stride;
        }
        if (w != 0.f) sum += w * values[at];
    }
    return sum;
}

Warp2D::Result Warp2D::sample(Point2 u, const float* param) const {
    const float eps = 1e-7f;
    u.x = std::clamp(u.x, eps, 1.f - eps);
    u.y = std::clamp(u.y, eps, 1.f - eps);
    const Corners c = corners(param);
    const uint32_t w = uint32_t(width_), h = uint32_t(height_), size = w * h;
    // The row interval by the marginal, then where in it (the rows' totals r0, r1).
    const uint32_t moff = c.slice * h;
    auto marginal = [&](uint32_t i) { return lookup(marginal_cdf_, moff + i, h, c); };
    const uint32_t row = find_interval(h, [&](uint32_t i) { return marginal(i) < u.y; });
    uint32_t off = row * w + c.slice * size;
    const float r0 = lookup(conditional_cdf_, off + w - 1, size, c),
                r1 = lookup(conditional_cdf_, off + 2 * w - 1, size, c);
    const float fy = solve_linear_mass(r0, r1, u.y - marginal(row));
    // The column by the conditional between the two rows, then where in the cell.
    const float mass_x = u.x * ((1.f - fy) * r0 + fy * r1);
    auto conditional = [&](uint32_t i) {
        return (1.f - fy) * lookup(conditional_cdf_, off + i, size, c) +
               fy * lookup(conditional_cdf_, off + w + i, size, c);
    };
    const uint32_t col = find_interval(w, [&](uint32_t i) { return conditional(i) < mass_x; });
    const float rest = mass_x - conditional(col);
    float c0, c1;
    edges(off + col, fy, c, c0, c1);
    const float fx = solve_linear_mass(c0, c1, rest);
    return {{(float(col) + fx) / float(w - 1), (float(row) + fy) / float(h - 1)},
            ((1.f - fx) * c0 + fx * c1) * float(w - 1) * float(h - 1)};
}

void Warp2D::edges(uint32_t offset, float fy, const Corners& c, float& c0, float& c1) const {
    const uint32_t w = uint32_t(width_), size = w * uint32_t(height_);
    c0 = (1.f - fy) * lookup(data_, offset, size, c) + fy * lookup(data_, offset + w, size, c);
    c1 = (1.f - fy) * lookup(data_, offset + 1, size, c) +
         fy * lookup(data_, offset + w + 1, size, c);
}

Warp2D::Cell Warp2D::cell_at(Point2 p, const Corners& c) const {
    const uint32_t w = uint32_t(width_), h = uint32_t(height_);
    const float x = p.x * float(w - 1), y = p.y * float(h - 1);
    Cell cell;
    cell.col = std::min(uint32_t(std::max(x, 0.f)), w - 2);
    cell.row = std::min(uint32_t(std::max(y, 0.f)), h - 2);
    cell.fx = x - float(cell.col);
    cell.fy = y - float(cell.row);
    cell.offset = cell.col + cell.row * w + c.slice * w * h;
    edges(cell.offset, cell.fy, c, cell.c0, cell.c1);
    return cell;
}

Warp2D::Result Warp2D::invert(Point2 p, const float* param) const {
    const Corners c = corners(param);
    const uint32_t w = uint32_t(width_), h = uint32_t(height_), size = w * h;
    const Cell k = cell_at(p, c);
    const float fx = k.fx, fy = k.fy;
    // x: the mass before the cell in the interpolated row, plus the cell's up to fx, over the
    // interpolated row's total.
    float ux = fx * (k.c0 + 0.5f * fx * (k.c1 - k.c0));
    ux += (1.f - fy) * lookup(conditional_cdf_, k.offset, size, c) +
          fy * lookup(conditional_cdf_, k.offset + w, size, c);
    const uint32_t roff = k.row * w + c.slice * size;
    const float r0 = lookup(conditional_cdf_, roff + w - 1, size, c),
                r1 = lookup(conditional_cdf_, roff + 2 * w - 1, size, c);
    ux /= (1.f - fy) * r0 + fy * r1;
    // y: the marginal mass below the row plus the row interval's up to fy.
    float uy = fy * (r0 + 0.5f * fy * (r1 - r0));
    uy += lookup(marginal_cdf_, k.row + c.slice * h, h, c);
    const float pdf = (1.f - fx) * k.c0 + fx * k.c1;
    return {{ux, uy}, pdf * float(w - 1) * float(h - 1)};
}

float Warp2D::eval(Point2 p, const float* param) const {
    const Cell k = cell_at(p, corners(param));
    return ((1.f - k.fx) * k.c0 + k.fx * k.c1) * float(width_ - 1) * float(height_ - 1);
}

}  // namespace foton
