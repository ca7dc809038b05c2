#include "grid_flights.h"

#include "kernels/majorant_march.h"

namespace foton {

void GridFlights::clear() {
    slot_.clear();
    medium_.clear();
    o_.clear();
    d_.clear();
    t_end_.clear();
    beta_.clear();
    result_.clear();
    t_.clear();
}

void GridFlights::add(uint32_t slot, int32_t medium, const Vec3& o, const Vec3& d, float t_end,
                      const RGB& beta) {
    slot_.push_back(slot);
    medium_.push_back(medium);
    o_.push_back(o);
    d_.push_back(d);
    t_end_.push_back(t_end);
    beta_.push_back(beta);
    result_.emplace_back();
    t_.push_back(0.f);
    t_hit_.resize(slot_.size());
    maj_of_.resize(slot_.size());
    collided_.resize(slot_.size());
}

void GridFlights::march(const Scene& scene, int32_t medium, bool simd) {
    row_.clear();
    for (uint32_t i : live_)
        if (medium_[i] == medium) row_.push_back(i);
    const std::size_t n = row_.size();
    for (auto* v : {&ox_, &oy_, &oz_, &dx_, &dy_, &dz_, &te_, &tau_rows_, &th_, &maj_})
        v->resize(n);
    hit_.resize(n);
    for (std::size_t r = 0; r < n; ++r) {
        const uint32_t i = row_[r];
        ox_[r] = o_[i].x;
        oy_[r] = o_[i].y;
        oz_[r] = o_[i].z;
        dx_[r] = d_[i].x;
        dy_[r] = d_[i].y;
        dz_[r] = d_[i].z;
        te_[r] = t_end_[i];
        th_[r] = t_[i];
        tau_rows_[r] = tau_[i];
    }
    const kern::MajorantGrid g = majorant_view(scene.media[std::size_t(medium)]);
    const kern::MarchFlights f{ox_.data(), oy_.data(),  oz_.data(), dx_.data(),
                               dy_.data(), dz_.data(),  te_.data(), tau_rows_.data(),
                               th_.data(), maj_.data(), hit_.data()};
    if (simd)
        kern::march_majorant(g, f, n);
    else
        kern::march_majorant_scalar(g, f, n);
    for (std::size_t r = 0; r < n; ++r) {
        const uint32_t i = row_[r];
        t_hit_[i] = th_[r];
        maj_of_[i] = maj_[r];
        collided_[i] = hit_[r];
    }
}

}  // namespace foton
