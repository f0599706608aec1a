// What every integrator that traces paths shares (path, direct, volpath, whitted, the
// photon mappers): next-event estimation, the multiple importance sampling weights, the
// depth limits and Russian roulette. The loops themselves live in the plugins
// (plugins/builtin/integrators/path.cpp is the one to read first).
#pragma once

#include <nori/camera.h>
#include <nori/color.h>
#include <nori/ray.h>
#include <nori/shape.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

namespace nori {

class BSDF;
class Emitter;
class PropertyList;
class Scene;
struct BSDFQueryRecord;
struct EmissionSample;
struct EmitterQueryRecord;
struct Intersection;

/// The balance heuristic weight of a sample taken with density `pdf` against another
/// strategy that would take it with density `otherPdf` (Veach 1997, §9.2.1).
inline float balanceHeuristic(float pdf, float otherPdf) {
    return pdf / (pdf + otherPdf);
}

/// One light sample at the surface point `its` (next-event estimation; PBR 4th ed.
/// §13.4.2): picks a light for its.p and its shading normal (pmf from
/// Scene::sampleEmitter), samples a point on
/// it, tests visibility and returns its contribution f·L·|cos θ|/(pdf·pmf) toward
/// wiLocal (local). With `mis`, the contribution carries the balance-heuristic weight
/// against BSDF sampling (delta lights keep weight 1). `emitterSample` picks the light,
/// `sample` the point on it.
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
/// `scatterPdf` is the solid-angle density with which the last vertex (lRec.ref, of
/// shading normal `refNormal`, zero in a medium) chose the ray.
Color3f emissionWithMIS(const Scene *scene, const Emitter &emitter, const EmitterQueryRecord &lRec,
                        const Normal3f &refNormal, bool specularBounce, float scatterPdf);

/// Paths traced from the lights (photons, light tracing) carry flux, not radiance. A BSDF
/// sample's weight (BSDF::sample: f·|cos θo|/pdf, radiance arriving along wo and leaving
/// along wi) times this factor is the weight of flux arriving along wi and leaving along
/// wo (world directions at `its`; bRec as sample() left it): flux is not scaled by 1/η²
/// across a refraction as radiance is (Veach 1997, §5.2), and shading normals make the
/// adjoint BSDF differ by |wi·ns||wo·ng|/(|wi·ng||wo·ns|) (Veach 1997, §5.3; PBR 3rd ed.
/// §16.1.3). Zero where a direction grazes the geometric or shading surface.
float adjointSampleFactor(const Intersection &its, const Vector3f &wi, const Vector3f &wo,
                          const BSDFQueryRecord &bRec);

/// A surface point of a light path connected to the camera (light tracing; bdpt's t = 1
/// strategies), made by connectToCamera.
struct CameraLink {
    CameraConnection camera;
    /// Where the shape's textures are filtered over the pixel footprint: the hit of the
    /// camera ray through camera.filmPosition, which shades the point (`traced` set).
    Intersection seen;
    bool traced = false;
    /// The intersection to shade the connected point `its` with.
    const Intersection &shading(const Intersection &its) const { return traced ? seen : its; }
};

/// Connects the surface point `its`, which light reaches from the world direction
/// toLight, to a point of the camera's lens chosen by `lensSample`, and tests the
/// visibility. Returns what a unit of flux arriving there adds to the film at
/// link.camera.filmPosition: f·|ns·ωL|·|ng·ωC|/|ng·ωL| times the camera's importance
/// (Veach 1997, §5.3: the flux crossed the geometric surface, the BSDF weighs it by the
/// shading cosine, the camera sees the geometric projected area), zero when the camera
/// does not see the point.
Color3f connectToCamera(const Scene &scene, const Intersection &its, const Vector3f &toLight,
                        const Point2f &lensSample, CameraLink &link);

/// The start of a path from the lights (photons, light tracing, bdpt): a light picked by
/// power with `emitterSample` (Scene::sampleEmitter), and its photon (Emitter::
/// sampleEmission, into `emission`). Returns the photon's flux over the light's pmf, whose
/// mean over the samples is the scene's total power, and sets `emitter` and `pmf`; zero
/// (and `emitter` nullptr or the flux invalid) when there is no light or sampling fails.
Color3f sampleLightPath(const Scene &scene, float emitterSample, const Point2f &positionSample,
                        const Point2f &directionSample, EmissionSample &emission,
                        const Emitter *&emitter, float &pmf);

/// Checks that paths traced from the lights can reach the camera of `scene`: a camera that
/// connect() supports and no participating media. Throws NoriException naming `plugin` and the offending object; `method`
/// names the technique in the message ("light tracing").
void requireLightPathScene(const Scene &scene, const std::string &plugin,
                           const std::string &method);

/// The light of every emitter at infinity (environment maps, constant backgrounds) that a
/// ray leaving the scene sees, in full: after a camera ray or a chain of specular bounces,
/// where no other strategy finds it. Filtered over the ray's footprint when it has
/// differentials.
Color3f lightAtInfinity(const Scene &scene, const Ray3f &ray);

/// How long a path may grow: `maxDepth` scattering events after the camera ray (−1: no
/// limit) and Russian roulette from event `rrDepth` on.
struct PathDepth {
    int maxDepth = -1;
    int rrDepth = 3;

    /// Reads `maxDepth` (default −1) and `rrDepth` (default 3); `plugin` names the
    /// integrator in errors.
    static PathDepth read(const PropertyList &props, const std::string &plugin);
    /// Whether a path that has scattered `events` times may scatter once more.
    bool mayScatter(int events) const { return maxDepth < 0 || events < maxDepth; }
};

/// Russian roulette after `events` scattering events (PBR 4th ed. §13.1.1): from rrDepth
/// on, the path continues with probability q = min(0.99, √(max throughput)) and its
/// throughput is divided by q, so the estimate stays unbiased. Returns whether it
/// continues. The square root is Cycles' (path_state_continuation_probability): it ends
/// fewer paths than q = max throughput, whose first roulette in a box of albedo 0.73
/// ends 61 % of them and leaves the rest with 2.6 times the weight. On the mesh-sphere
/// and Cornell boxes it gives 27-30 % less MSE for 8 % more rays (docs/design/figures.md);
/// the cap keeps paths of throughput 1 (mirrors, glass) finite.
inline bool russianRoulette(int events, int rrDepth, Color3f &throughput, float sample) {
    if (events < rrDepth)
        return true;
    const float q = std::min(0.99f, std::sqrt(throughput.maxCoeff()));
    if (sample >= q)
        return false;
    throughput /= q;
    return true;
}

} // namespace nori
