// Unidirectional path tracing with a choice of strategy for direct light — BSDF
// sampling, light sampling (next-event estimation) or both with multiple importance
// sampling (Veach 1997, ch. 9, balance heuristic). With one bounce it computes direct
// lighting only. The integrator plugins (direct_*, path_*) are configurations of it.
#pragma once

#include <nori/integrator.h>

#include <functional>

namespace nori {

class BSDF;
class Emitter;
struct EmitterQueryRecord;
class Sampler;
class Scene;
struct Intersection;

/// One light sample at the surface point `its` (next-event estimation): picks a light by
/// power, samples a point on it, tests visibility and returns its contribution
/// f·L·|cos θ|/(pdf·pmf) toward wiLocal. With `mis`, the contribution carries the
/// balance-heuristic weight against BSDF sampling (delta lights keep weight 1).
/// `emitterSample` picks the light, `sample` the point on it.
Color3f sampleDirectLight(const Scene *scene, const Intersection &its, const BSDF &bsdf,
                          const Vector3f &wiLocal, bool mis, float emitterSample,
                          const Point2f &sample);

/// The fraction of light that crosses a shadow ray from a surface toward a light (world
/// direction toLight): 0 or 1 for plain visibility, a transmittance through media.
using ShadowTransmittance = std::function<Color3f(const Ray3f &shadowRay, const Vector3f &toLight)>;
/// sampleDirectLight with the shadow ray's outcome given by `transmittance`.
Color3f sampleDirectLight(const Scene *scene, const Intersection &its, const BSDF &bsdf,
                          const Vector3f &wiLocal, bool mis, float emitterSample,
                          const Point2f &sample, const ShadowTransmittance &transmittance);

/// The emission `emitter` sends along a scattered (or camera) ray that found it: all of it
/// after a specular event, else weighted by the balance heuristic against next-event
/// estimation, whose density is the pmf of sampleEmitter times the light's own.
/// `scatterPdf` is the solid-angle density with which the last vertex chose the ray.
Color3f emissionWithMIS(const Scene *scene, const Emitter &emitter, const EmitterQueryRecord &lRec,
                        bool specularBounce, float scatterPdf);

class PathTracer : public Integrator {
public:
    enum class Strategy {
        BSDF,  ///< emission is found by BSDF-sampled rays only ("mats")
        Light, ///< emitters are sampled at each vertex ("ems")
        MIS    ///< both, weighted by the balance heuristic ("mis")
    };

    /// `bounces` > 0 fixes the number of bounces (1: direct lighting); otherwise the
    /// plugin reads `maxDepth` (default −1, unbounded) and `rrDepth` (default 3).
    PathTracer(const PropertyList &props, Strategy strategy, int bounces, std::string name);

    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const override;
    std::string toString() const override;

private:
    /// The emission of `emitter` that a BSDF-sampled (or camera) ray found, weighted for
    /// the strategy: all of it after a specular bounce or with BSDF sampling alone, none
    /// with light sampling alone (next-event estimation counted it), and the balance
    /// heuristic against light sampling with MIS.
    Color3f foundEmission(const Scene *scene, const Emitter &emitter,
                          const EmitterQueryRecord &lRec, bool specularBounce, float bsdfPdf) const;

    Strategy m_strategy;
    int m_maxDepth; ///< bounces after the camera ray; −1 for no limit
    int m_rrDepth;  ///< Russian roulette from this bounce on
    std::string m_name;
};

} // namespace nori
