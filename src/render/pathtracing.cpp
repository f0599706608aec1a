#include <nori/bsdf.h>
#include <nori/emitter.h>
#include <nori/pathtracing.h>
#include <nori/scene.h>
#include <nori/shading.h>

#include <algorithm>

namespace nori {

Color3f sampleDirectLight(const Scene *scene, const Intersection &its, const BSDF &bsdf,
                          const Vector3f &wiLocal, bool mis, float emitterSample,
                          const Point2f &sample) {
    return sampleDirectLight(scene, its, bsdf, wiLocal, mis, emitterSample, sample,
                             [scene](const Ray3f &shadowRay, const Vector3f &) {
                                 return Color3f(scene->rayIntersect(shadowRay) ? 0.0f : 1.0f);
                             });
}

Color3f sampleDirectLight(const Scene *scene, const Intersection &its, const BSDF &bsdf,
                          const Vector3f &wiLocal, bool mis, float emitterSample,
                          const Point2f &sample, const ShadowTransmittance &transmittance) {
    float u = emitterSample, pmf;
    const Emitter *emitter = scene->sampleEmitter(its.p, its.shFrame.n, u, pmf);
    if (!emitter || pmf == 0.0f)
        return Color3f(0.0f);
    EmitterQueryRecord lRec(its.p);
    lRec.refNormal = its.shFrame.n;
    const Color3f radianceOverPdf = emitter->sample(lRec, sample);
    // Light from below the geometric surface cannot reach a shading normal bent toward it.
    if ((radianceOverPdf == 0.0f).all() || !its.sidesAgree(lRec.wi))
        return Color3f(0.0f);
    const BSDFQueryRecord bRec(its, wiLocal, its.toLocal(lRec.wi), ESolidAngle);
    const Color3f f = bsdf.eval(bRec);
    if ((f == 0.0f).all())
        return Color3f(0.0f);
    // The shadow ray last: it is the expensive part, and f = 0 makes it moot.
    const Color3f visible = transmittance(its.spawnRayTo(lRec.p), lRec.wi);
    if ((visible == 0.0f).all())
        return Color3f(0.0f);
    Color3f contribution =
        f * radianceOverPdf * visible * (std::abs(Frame::cosTheta(bRec.wo)) / pmf);
    if (mis && !emitter->isDelta())
        // Against BSDF sampling of the same direction.
        contribution *= balanceHeuristic(pmf * lRec.pdf, bsdf.pdf(bRec));
    return contribution;
}

Color3f emissionWithMIS(const Scene *scene, const Emitter &emitter, const EmitterQueryRecord &lRec,
                        const Normal3f &refNormal, bool specularBounce, float scatterPdf) {
    Color3f le = emitter.eval(lRec);
    if (specularBounce || (le == 0.0f).all())
        return le;
    // The density of sampleDirectLight's choice, which knew the normal at ref.
    EmitterQueryRecord query = lRec;
    query.refNormal = refNormal;
    const float lightPdf = scene->emitterPmf(lRec.ref, refNormal, &emitter) * emitter.pdf(query);
    return le * balanceHeuristic(scatterPdf, lightPdf);
}

Color3f connectToCamera(const Scene &scene, const Intersection &its, const Vector3f &toLight,
                        const Point2f &lensSample, CameraLink &link) {
    CameraConnection &camera = link.camera;
    if (!scene.getCamera()->connect(its.p, lensSample, camera))
        return Color3f(0.0f);
    // Where the shape's textures are filtered over the pixel footprint, the point is
    // shaded as the camera ray through that pixel shades it, with that ray's
    // differentials (raydifferential.h), so that the camera and the light paths see the
    // same surface (a filtered normal map is not the mean of its normals). That ray also
    // tests the visibility: it must find this point again, to within kSamePoint of its
    // distance from the lens (the film position's rounding moves it by about 1e-7).
    constexpr float kSamePoint = 1e-4f;
    if (usesFootprint(*its.shape)) {
        Ray3f cameraRay;
        if ((scene.sampleCameraRay(cameraRay, camera.filmPosition, lensSample) == 0.0f).all() ||
            !scene.rayIntersect(cameraRay, link.seen) || link.seen.shape != its.shape ||
            (link.seen.p - its.p).norm() > kSamePoint * camera.distance ||
            !link.seen.sidesAgree(toLight))
            return Color3f(0.0f);
        link.traced = true;
    }
    const Intersection &shading = link.shading(its);
    // f for light arriving along toLight and leaving toward the camera: in the BSDF's
    // convention wi is the direction toward the camera.
    const BSDFQueryRecord query(shading, shading.toLocal(camera.direction),
                                shading.toLocal(toLight), ESolidAngle);
    const Color3f f = shading.shape->getBSDF()->eval(query);
    const float cosLightGeometric = std::abs(toLight.dot(its.geoFrame.n));
    if ((f == 0.0f).all() || cosLightGeometric == 0.0f)
        return Color3f(0.0f);
    // Radiance = flux·f·|ωL·ns|/|ωL·ng| per projected area (Veach 1997, §5.3).
    Color3f response = f * std::abs(Frame::cosTheta(query.wo)) *
                       std::abs(camera.direction.dot(its.geoFrame.n)) / cosLightGeometric *
                       camera.importance;
    if ((response == 0.0f).all() ||
        (!link.traced && scene.rayIntersect(its.spawnRayTo(camera.lensPoint))))
        return Color3f(0.0f);
    return response;
}

Color3f sampleLightPath(const Scene &scene, float emitterSample, const Point2f &positionSample,
                        const Point2f &directionSample, EmissionSample &emission,
                        const Emitter *&emitter, float &pmf) {
    pmf = 0.0f;
    emitter = scene.sampleEmitter(emitterSample, pmf);
    if (!emitter || pmf == 0.0f)
        return Color3f(0.0f);
    Color3f flux = emitter->sampleEmission(emission, positionSample, directionSample) / pmf;
    return flux.isValid() ? flux : Color3f(0.0f);
}

void requireLightPathScene(const Scene &scene, const std::string &plugin,
                           const std::string &method) {
    const Camera *camera = scene.getCamera();
    if (!camera->canConnect())
        throw NoriException("{}: the camera '{}' cannot be connected to from the scene (its "
                            "rays pass a lens system); use perspective or thinlens",
                            plugin, camera->pluginName());
    const auto &shapes = scene.getShapes();
    if (camera->getMedium() || std::any_of(shapes.begin(), shapes.end(), [](const auto &shape) {
            return shape->hasMediumInterface();
        }))
        throw NoriException("{}: the scene has participating media, which {} does not "
                            "render; use volpath",
                            plugin, method);
}

Color3f lightAtInfinity(const Scene &scene, const Ray3f &ray) {
    Color3f radiance(0.0f);
    for (const Emitter *emitter : scene.getInfiniteEmitters())
        radiance += emitter->eval(EmitterQueryRecord(ray, true));
    return radiance;
}

float adjointSampleFactor(const Intersection &its, const Vector3f &wi, const Vector3f &wo,
                          const BSDFQueryRecord &bRec) {
    const float cosInGeometric = std::abs(wi.dot(its.geoFrame.n));
    const float cosOutShading = std::abs(Frame::cosTheta(bRec.wo));
    if (cosInGeometric == 0.0f || cosOutShading == 0.0f)
        return 0.0f;
    return bRec.eta * bRec.eta * std::abs(Frame::cosTheta(bRec.wi)) *
           std::abs(wo.dot(its.geoFrame.n)) / (cosInGeometric * cosOutShading);
}

PathDepth PathDepth::read(const PropertyList &props, const std::string &plugin) {
    PathDepth depth;
    depth.maxDepth = props.getInteger("maxDepth", -1);
    depth.rrDepth = props.getInteger("rrDepth", 3);
    if (depth.maxDepth == 0 || depth.maxDepth < -1)
        throw NoriException("{}: 'maxDepth' must be positive or -1 (unbounded), got {}", plugin,
                            depth.maxDepth);
    if (depth.rrDepth < 1)
        throw NoriException("{}: 'rrDepth' must be at least 1, got {}", plugin, depth.rrDepth);
    return depth;
}

} // namespace nori
