#pragma once
// Volumetric path tracing (`type="volpath"`): the path tracer of path/ with participating media
// (scene/medium.h) between the surfaces. A path's ray samples a free flight through the medium
// it is in by delta tracking (transport/common/medium_tracking.h): it scatters in the medium
// (a vertex with the Henyey-Greenstein phase function in place of a BSDF), is absorbed, or
// reaches the surface ahead. At every vertex, surface or medium, one light sample (next event
// estimation) is weighed against phase or BSDF sampling by the renderer's MIS heuristic; its
// shadow ray carries the transmittance of every medium it crosses and passes the interfaces
// that bound them (common/medium_shadow.h). Surfaces with an interface material are no vertex:
// the ray goes on through them into the medium beyond. The medium's emission is gathered
// along the free flights. max_depth counts scattering vertices of both kinds, as pbrt-v4's
// volpath does; Russian roulette from rr_depth as in path.
//
// The shading here is scalar, one vertex at a time (the SIMD shading kernels of path/ do not
// know media); rays, shadow rays and their rounds through interfaces go through the
// accelerator as whole batches. Without media it renders the path tracer's expected image.
#include "engine/accel/intersector.h"
#include "engine/core/params.h"
#include "engine/transport/common/medium_tracking.h"
#include "engine/transport/run/render_options.h"
#include "engine/transport/run/render_settings.h"

namespace foton {

// The kernel that finds grid media's tentative collisions: the SIMD majorant march or its
// scalar twin (the same images, bit for bit; for measuring the kernel).
enum class FlightKernel : uint8_t { Simd, Scalar };

struct VolPathSettings {
    // How shadow rays weigh the media they cross: exact (exp(-sigma_t d), homogeneous media)
    // or ratio tracking's unbiased estimate (`transmittance="ratio"`).
    TransmittanceEstimator transmittance = TransmittanceEstimator::Exact;
    // How paths sample their flights: analytically (per channel, MIS over the channels) or by
    // delta tracking (`free_flight="delta"`).
    FreeFlightSampling free_flight = FreeFlightSampling::Analytic;
    FlightKernel flight_kernel = FlightKernel::Simd;
    // Spectral rendering (`spectral="true"`, core/spectrum.h): each path carries three
    // wavelengths, every RGB input upsampled to a spectrum where the path meets it, and the
    // film takes the samples through the CIE colour matching functions to sRGB. What chromatic
    // media need to agree with a spectral renderer (RGB's exp(-sigma_R d) is not the red
    // channel of exp(-sigma(lambda) d)); not with subsurface materials.
    bool spectral = false;
};

// The row's parse: `transmittance`, `free_flight`, `flight_kernel` and `spectral` into
// RenderSettings::own.
void parse_volpath(const ParamSet& params, RenderSettings& settings);
// The row's render: the tile driver over volumetric path tracing.
RenderResult render_volpath(const Scene& scene, const RenderSettings& settings,
                            const Intersector& accel, const RenderOptions& options);

}  // namespace foton
