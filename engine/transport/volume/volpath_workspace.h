#pragma once
// volpath's per-bounce state: the batch of rays in flight and each path's throughput and
// history, by slot (volpath.cpp).
#include <cstdint>
#include <vector>

#include "engine/core/ray_batch.h"
#include "engine/core/spectrum.h"
#include "engine/core/stats.h"
#include "engine/transport/common/camera_integrator.h"
#include "engine/transport/common/medium_shadow.h"
#include "engine/transport/common/path_sampler.h"
#include "engine/transport/common/wavefront.h"
#include "grid_flights.h"

namespace foton {

struct VolPathWorkspace : IntegratorWorkspace {
    RayBatch rays, next;
    HitBatch hits;
    MediumShadowRays shadow;
    // Per path, by slot.
    std::vector<RGB> beta;
    std::vector<float> eta_scale;        // product of eta^2 over refractions (roulette)
    std::vector<float> pdf_prev;         // solid-angle pdf of the sample that made the ray
    std::vector<uint8_t> specular_prev;  // ... and whether it came from a delta lobe
    std::vector<Vec3> p_prev, n_prev;    // where it started (normal zero in a medium)
    std::vector<int32_t> medium;         // the medium the ray travels in
    std::vector<uint32_t> vertices;      // scattering vertices so far (surface or medium)
    std::vector<uint8_t> rough;          // some vertex scattered non-specularly (regularize)
    std::vector<uint32_t> crossings;     // interfaces passed
    std::vector<uint32_t> draws;         // free-flight numbers drawn (kMediumStream)
    std::vector<uint64_t> keys;
    std::vector<PathSampler> samplers;
    std::vector<Wavelengths> wavelengths;  // spectral mode: each path's three
    // The bounce's flights through grid media, tracked as one batch before shading, and each
    // ray's flight there (-1: none).
    GridFlights flights;
    std::vector<int32_t> flight_of;
    TraceCounters probes;  // the bounce's subsurface probes (traced one by one)
};

}  // namespace foton
