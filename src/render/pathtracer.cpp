#include <nori/bsdf.h>
#include <nori/emitter.h>
#include <nori/pathtracer.h>
#include <nori/raydifferential.h>
#include <nori/sampler.h>
#include <nori/scene.h>

namespace nori {

PathTracer::PathTracer(const PropertyList &props, Strategy strategy, int bounces, std::string name)
    : m_strategy(strategy), m_name(std::move(name)) {
    if (bounces > 0) {
        m_maxDepth = bounces;
        m_rrDepth = bounces + 1; // never
    } else {
        m_maxDepth = props.getInteger("maxDepth", -1);
        m_rrDepth = props.getInteger("rrDepth", 3);
        if (m_maxDepth == 0 || m_maxDepth < -1)
            throw NoriException("{}: 'maxDepth' must be positive or -1 (unbounded), got {}", m_name,
                                m_maxDepth);
        if (m_rrDepth < 1)
            throw NoriException("{}: 'rrDepth' must be at least 1, got {}", m_name, m_rrDepth);
    }
}

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
    const Emitter *emitter = scene->sampleEmitter(u, pmf);
    if (!emitter || pmf == 0.0f)
        return Color3f(0.0f);
    EmitterQueryRecord lRec(its.p);
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
    if (mis && !emitter->isDelta()) {
        // Balance heuristic against BSDF sampling of the same direction.
        const float lightPdf = pmf * lRec.pdf, bsdfPdf = bsdf.pdf(bRec);
        contribution *= lightPdf / (lightPdf + bsdfPdf);
    }
    return contribution;
}

Color3f PathTracer::Li(const Scene *scene, Sampler *sampler, const Ray3f &cameraRay) const {
    Color3f radiance(0.0f), throughput(1.0f);
    Ray3f ray = cameraRay;
    bool specularBounce = true; // the camera "bounce": emission seen directly counts fully
    float bsdfPdf = 0.0f;       // density of the direction of `ray`, for MIS
    Point3f previous = ray.o;
    for (int depth = 0;; ++depth) {
        Intersection its;
        if (!scene->rayIntersect(ray, its)) {
            // The ray leaves the scene and sees the lights at infinity. Camera rays and
            // specular chains (weight 1, no MIS) may use a filtered lookup; others must
            // see exactly what the light's sampling density assumes.
            for (const Emitter *emitter : scene->getInfiniteEmitters())
                radiance += throughput * foundEmission(scene, *emitter,
                                                       EmitterQueryRecord(ray, specularBounce),
                                                       specularBounce, bsdfPdf);
            break;
        }
        if (const Emitter *emitter = its.shape->getEmitter())
            radiance +=
                throughput * foundEmission(scene, *emitter, EmitterQueryRecord(previous, its),
                                           specularBounce, bsdfPdf);

        if (m_maxDepth > 0 && depth >= m_maxDepth)
            break;

        // Every bounce draws the same dimensions in the same order, used or not, so that
        // a dimension of a low-discrepancy sampler means the same thing in every sample.
        const float emitterSample = sampler->next1D();
        const Point2f lightSample = sampler->next2D();
        const Point2f bsdfSample = sampler->next2D();
        const float rouletteSample = sampler->next1D();

        const BSDF *bsdf = its.shape->getBSDF();
        const Vector3f wiLocal = its.toLocal(-ray.d);
        // Light sampling pays off only where the BSDF has a non-delta lobe.
        if (m_strategy != Strategy::BSDF && bsdf->isDiffuse())
            radiance += throughput * sampleDirectLight(scene, its, *bsdf, wiLocal,
                                                       m_strategy == Strategy::MIS, emitterSample,
                                                       lightSample);

        BSDFQueryRecord bRec(its, wiLocal);
        const Color3f weight = bsdf->sample(bRec, bsdfSample);
        if ((weight == 0.0f).all() || !its.sidesAgree(its.toWorld(bRec.wo)))
            break;
        specularBounce = bRec.measure == EDiscrete || !bsdf->isDiffuse();
        bsdfPdf = bRec.measure == EDiscrete ? 0.0f : bsdf->pdf(bRec);
        throughput *= weight;
        previous = its.p;
        ray = spawnScatteredRay(its, ray, bRec);

        // Russian roulette: continue with probability q, and divide by it.
        if (depth + 1 >= m_rrDepth) {
            const float q = std::min(0.99f, throughput.maxCoeff());
            if (rouletteSample >= q)
                break;
            throughput /= q;
        }
    }
    return radiance;
}

Color3f PathTracer::foundEmission(const Scene *scene, const Emitter &emitter,
                                  const EmitterQueryRecord &lRec, bool specularBounce,
                                  float bsdfPdf) const {
    if (specularBounce || m_strategy == Strategy::BSDF)
        return emitter.eval(lRec);
    if (m_strategy == Strategy::Light)
        return Color3f(0.0f); // next-event estimation counted this light already
    return emissionWithMIS(scene, emitter, lRec, false, bsdfPdf);
}

Color3f emissionWithMIS(const Scene *scene, const Emitter &emitter, const EmitterQueryRecord &lRec,
                        bool specularBounce, float scatterPdf) {
    Color3f le = emitter.eval(lRec);
    if (specularBounce || (le == 0.0f).all())
        return le;
    const float lightPdf = scene->emitterPmf(&emitter) * emitter.pdf(lRec);
    return le * (scatterPdf / (scatterPdf + lightPdf));
}

std::string PathTracer::toString() const {
    return fmt::format("{}[maxDepth={}, rrDepth={}]", m_name, m_maxDepth, m_rrDepth);
}

} // namespace nori
