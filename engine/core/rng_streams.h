#pragma once
// Every random stream's key, in one place. Random numbers are counter-based, keyed by (seed,
// stream, index, dimension) (core/rng.h), so two users of one stream key would draw the same
// numbers and correlate; a new stream takes a new value here, and tests/test_sampler.cpp checks
// that they stay distinct. (The samplers' internal scrambling keys are not streams and stay
// in core/halton.cpp and core/zsobol.cpp.)
#include <cstdint>

namespace foton {

enum RandomStream : uint64_t {
    kPixelStream = 1,                   // a pixel's sample pattern (with Sobol': every dimension)
    kLightStream = 2,                   // light choice and light samples at camera vertices
    kPathStream = 3,                    // camera paths: BSDF samples and roulette
    kLightPathStream = 4,               // the light tracer's paths
    kLensStream = 5,                    // thin-lens positions of camera rays
    kPhotonStream = 16,                 // photons: emission and bounces
    kSppmStream = 32,                   // SPPM's camera pass to the visible points
    kAoStream = 0xa0,                   // ambient-occlusion probe rays
    kPhotonGatherStream = 0x6a7,        // photon mapping's final-gather rays at a visible point
    kCacheStream = 0x1cac,              // irradiance-cache records and their lookups
    kBidirLightStream = 0xb1d1,         // bdpt/bpm/vcm light subpaths
    kBidirCameraStream = 0xb1d2,        // bdpt/bpm/vcm camera subpaths
    kCacheVertexChoiceStream = 0xc401,  // path + cache: delta or diffuse at the cache's vertex
    kAovStream = 0xa0f,                 // the albedo AOV's BSDF samples
    kMediumStream = 0x3ed1,             // volumetric paths: free flights and collisions
    kMediumShadowStream = 0x3ed2,       // ratio tracking along shadow rays through media
    kVolumePhotonStream = 0x3ed3,       // volumetric photon mapping's photons
    kVolumeCameraStream = 0x3ed4,       // volumetric photon mapping's camera paths
    kVolumeLightStream = 0x3ed5,        // light tracing's paths through media
    kBidirLightMediumStream = 0xb1d3,   // bdpt/vcm light subpaths' free flights
    kBidirCameraMediumStream = 0xb1d4,  // bdpt/vcm camera subpaths' free flights
    kImportonStream = 0x1e01,           // importons: their pixels and bounces
    kImportonStoreStream = 0x1e02,      // photon storage decided by the importon map
    kMltBootstrapStream = 0x3171,       // MLT: the bootstrap's primary samples
    kMltChainStream = 0x3172,           // MLT: chain starts, proposals and acceptance
    kAdaptivePhotonStream = 0xa9f0,     // adaptive photon tracing: uniform proposals
    kAdaptiveMutationStream = 0xa9f1,   // adaptive photon tracing: mutations
    kSubsurfaceStream = 0x55b0,         // subsurface scattering: probes, exits, exit lights
    kWavelengthStream = 0x5bec,         // spectral paths: their wavelengths
};

inline constexpr RandomStream kAllRandomStreams[] = {kPixelStream,
                                                     kLightStream,
                                                     kPathStream,
                                                     kLightPathStream,
                                                     kLensStream,
                                                     kPhotonStream,
                                                     kSppmStream,
                                                     kAoStream,
                                                     kPhotonGatherStream,
                                                     kCacheStream,
                                                     kBidirLightStream,
                                                     kBidirCameraStream,
                                                     kCacheVertexChoiceStream,
                                                     kAovStream,
                                                     kMediumStream,
                                                     kMediumShadowStream,
                                                     kVolumePhotonStream,
                                                     kVolumeCameraStream,
                                                     kVolumeLightStream,
                                                     kWavelengthStream,
                                                     kBidirLightMediumStream,
                                                     kBidirCameraMediumStream,
                                                     kImportonStream,
                                                     kImportonStoreStream,
                                                     kMltBootstrapStream,
                                                     kMltChainStream,
                                                     kAdaptivePhotonStream,
                                                     kAdaptiveMutationStream,
                                                     kSubsurfaceStream};

}  // namespace foton
