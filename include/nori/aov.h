// Arbitrary output variables: per-pixel layers written beside the beauty image, as the
// features a denoiser needs (albedo, normal, depth, position) and statistics of the
// render itself (sampleCount, variance).
#pragma once

#include <nori/color.h>
#include <nori/ray.h>

#include <string>
#include <vector>

namespace nori {

class Scene;

enum class AOV {
    Albedo,      ///< the BSDF's albedo at the first non-specular hit (0 where none)
    Normal,      ///< the shading normal there, world space (0 where none)
    Depth,       ///< distance from the camera to the first hit (0 where the ray escapes)
    Position,    ///< world position of the first hit (0 where the ray escapes)
    SampleCount, ///< samples taken in the pixel (adaptive sampling varies it)
    Variance,    ///< variance of the pixel's mean, from two interleaved half-buffers
    Emission,    ///< light emitted toward the camera where its ray first hits (emitters'
                 ///< own pixels, the lights at infinity where it escapes), 0 elsewhere
};

/// The layer name in the EXR ("albedo") and the names of its channels ("R", "G", "B").
const char *aovName(AOV aov);
const std::vector<std::string> &aovChannels(AOV aov);

/// Parses a list such as "albedo,normal" (commas and/or spaces; duplicates dropped,
/// order kept). Throws NoriException naming an unknown entry, with a "did you
/// mean". `where` names the source in messages ("--aovs").
std::vector<AOV> parseAOVList(const std::string &list, const std::string &where);

/// The surface AOVs of one camera sample.
struct SurfaceAOVs {
    Color3f albedo{0.0f};
    Vector3f normal = Vector3f::Zero();
    float depth = 0.0f;
    Point3f position = Point3f::Zero();
    Color3f emission{0.0f};
};

/// Traces a camera ray for its surface AOVs: depth, position and emission at the first hit
/// (or the light at infinity where it escapes); albedo and normal at the first hit whose
/// BSDF is not specular, following up to eight specular reflections or refractions:
/// through smooth glass (BSDF::discreteLobes) its more probable lobe, through other
/// specular BSDFs a lobe sampled with random numbers from `seed` (not the integrator's
/// sampler, whose dimensions stay as they are).
SurfaceAOVs traceSurfaceAOVs(const Scene &scene, const Ray3f &cameraRay, uint64_t seed);

} // namespace nori
