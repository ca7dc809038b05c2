// PhotonMap's photons as bytes, for the maps an MPI render assembles from every rank's
// share of a pass (photon_tracer.cpp).
#include "photon_map.h"

namespace foton {

void PhotonMap::pack(Bytes& out) const {
    foton::pack(out, x_);
    foton::pack(out, y_);
    foton::pack(out, z_);
    foton::pack(out, power_);
    foton::pack(out, dir_);
    foton::pack(out, normal_);
    foton::pack(out, flags_);
    foton::pack(out, light_);
}

void PhotonMap::unpack_append(Unpacker& in) {
    in.append(x_);
    in.append(y_);
    in.append(z_);
    in.append(power_);
    in.append(dir_);
    in.append(normal_);
    in.append(flags_);
    in.append(light_);
}

}  // namespace foton
