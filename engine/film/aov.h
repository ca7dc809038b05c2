#pragma once
// Arbitrary output variables (AOVs): images a render writes beside its radiance, as extra
// channels of the same OpenEXR file, named as pbrt-v4's G-buffer film names them (and
// OpenEXR's standard `Z` for depth). What each holds:
//   albedo    Albedo.R/G/B  the first surface's reflectance: the BSDF's directional albedo
//                           towards the camera ray, estimated from 16 stratified BSDF samples
//                           (exact for Lambert); 0 where the ray leaves the scene
//   normal    N.X/Y/Z       geometric normal, facing the camera ray, in camera space
//             Ns.X/Y/Z      shading normal (interpolated), likewise
//   depth     Z             camera-space z of the first surface (distance along the view axis);
//                           +inf where no sample of the pixel hit anything
//   position  P.X/Y/Z       the first surface's point in camera space (the EXR's worldToCamera
//                           attribute maps world space to it)
//   variance  Variance.R/G/B  the sample variance of the pixel's radiance samples (per sample,
//                           as pbrt-v4: the variance of the pixel's mean is this / samples)
//   samples   samples       the samples each pixel averages (a UINT channel)
//   components <name>.R/G/B  what each part of the integrator's estimate adds (photon
//                           mapping: emitted, direct, caustic, indirect or photon_map)
// Normal, depth and position average the pixel's samples that hit a surface (0, or +inf for
// depth, where none did); albedo averages all of them, as the radiance does.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/core/params.h"

namespace foton {

enum AovBits : uint32_t {
    kAovAlbedo = 1u << 0,
    kAovNormal = 1u << 1,
    kAovDepth = 1u << 2,
    kAovPosition = 1u << 3,
    kAovVariance = 1u << 4,
    kAovSamples = 1u << 5,
    // The integrator's components (photon mapping: emitted, direct, caustic, indirect), each
    // a layer of its own; they add up to the image.
    kAovComponents = 1u << 6,
    // The ones the first-hit pass (G-buffer) computes, for any integrator.
    kAovFirstHit = kAovAlbedo | kAovNormal | kAovDepth | kAovPosition,
    kAovAll = kAovFirstHit | kAovVariance | kAovSamples | kAovComponents,
};

// albedo, normal, depth, position, variance, samples (and `all`), one bit each.
const EnumTable<uint32_t>& aov_names();
// "albedo,normal": the bits of a comma-separated list; false with `bad` the unknown name.
// `named` (optional) gets the bits of the names other than `all`.
bool parse_aov_list(const std::string& text, uint32_t& bits, std::string& bad,
                    uint32_t* named = nullptr);
// The names of `bits`, comma-separated, in aov_names()' order.
std::string aov_list_text(uint32_t bits);

// The EXR channels of the AOVs in `bits`, in aov.h's order (the samples channel last; the
// components' depend on the integrator and are not among them).
std::vector<std::string> aov_channels(uint32_t bits);

// One AOV's channels over the film: `values` holds channels.size() floats per pixel, pixel by
// pixel in the film's row-major order.
struct AovLayer {
    std::string name;                   // the AOV's name ("albedo")
    std::vector<std::string> channels;  // the EXR channel names ("Albedo.R", ...)
    std::vector<float> values;
    std::size_t stride() const { return channels.size(); }
    float at(std::size_t pixel, std::size_t channel) const {
        return values[pixel * channels.size() + channel];
    }
};

// The samples AOV as a float layer (for a viewer; the EXR writes it as a UINT channel).
AovLayer samples_layer(const std::vector<uint32_t>& samples_per_pixel);

// The layer called `name` in `layers`, or null.
const AovLayer* find_aov(const std::vector<AovLayer>& layers, const std::string& name);

}  // namespace foton
