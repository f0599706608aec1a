// Sampling routines ready for the χ² test: every warp by name, and the direction
// sampling of a BSDF, a phase function or an emitter.
#pragma once

#include <nori/chisquare.h>
#include <nori/texture.h>

namespace nori {

class BSDF;
class PhaseFunction;
class Emitter;

/// A warp of warp.h, by name, with its parameter (if it has one).
struct NamedWarp {
    std::string name;
    std::string parameterName; ///< "" for warps without a parameter
    float defaultParameter = 0.0f;
    std::function<SamplingRoutine(float parameter)> routine;
};

/// All warps of warp.h.
const std::vector<NamedWarp> &namedWarps();
/// The warp called `name`; throws NoriException (with a did-you-mean) otherwise.
const NamedWarp &findWarp(const std::string &name);

/// wo sampled by bsdf.sample() for the incident direction wi (local frame), against
/// bsdf.pdf(), at the texture lookup point `where`. Discrete lobes and failed samples are
/// not binned.
SamplingRoutine bsdfRoutine(const BSDF &bsdf, const Vector3f &wi,
                            const TextureQuery &where = TextureQuery());
/// wo sampled by phase.sample() for wi, against phase.pdf().
SamplingRoutine phaseRoutine(const PhaseFunction &phase, const Vector3f &wi);
/// Directions toward the light sampled from `ref`, against emitter.pdf(), in a frame whose
/// +x points at the centre of the light's shape (so the light lies on the histogram's
/// equator). For an area light the queried direction is traced to its shape to find p
/// and n. `refNormal` is the shading normal at ref the light is told (zero: none).
SamplingRoutine emitterRoutine(const Emitter &emitter, const Point3f &ref,
                               const Normal3f &refNormal = Normal3f::Zero());
/// A reference point from which to test an emitter, chosen by `u`: on a sphere around
/// its shape's bounding box, at a distance of the box's diagonal from its centre (near
/// enough that the light covers several histogram bins); for shapeless lights, on the
/// unit sphere.
Point3f emitterReferencePoint(const Emitter &emitter, const Point2f &u);

} // namespace nori
