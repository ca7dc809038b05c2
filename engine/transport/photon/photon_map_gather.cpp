// An MPI render's photon map: every rank's share of a pass, assembled on every rank
// (photon_tracer.cpp).
#include "photon_map.h"

namespace foton {

void PhotonMap::all_gather(const Cluster& cluster) {
    // Array by array, straight into the assembled arrays: a 100M-photon map is 3 GB.
    cluster.all_gather_concat(x_);
    cluster.all_gather_concat(y_);
    cluster.all_gather_concat(z_);
    cluster.all_gather_concat(power_);
    cluster.all_gather_concat(dir_);
    cluster.all_gather_concat(normal_);
    cluster.all_gather_concat(flags_);
    cluster.all_gather_concat(light_);
}

}  // namespace foton
