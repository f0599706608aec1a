/*
 * whitted — Nori's Whitted-style ray tracer: at a diffuse surface, emission plus one
 * emitter sample; at a specular one (mirror, glass), continue the path with
 * probability 0.95 (Russian roulette, dividing by 0.95) along the sampled direction.
 *
 * No parameters.
 *
 *   <integrator type="whitted"/>
 */
#include <nori/bsdf.h>
#include <nori/emitter.h>
#include <nori/integrator.h>
#include <nori/pathtracing.h>
#include <nori/raydifferential.h>
#include <nori/sampler.h>
#include <nori/scene.h>

namespace nori {
namespace {

class WhittedIntegrator : public Integrator {
public:
    explicit WhittedIntegrator(const PropertyList &props) { (void)props; }

    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const override {
        Intersection its;
        if (!scene->rayIntersect(ray, its))
            // Only camera rays and specular chains get here: lights at infinity count fully.
            return lightAtInfinity(*scene, ray);
        Color3f radiance(0.0f);
        if (const Emitter *emitter = its.shape->getEmitter())
            radiance += emitter->eval(EmitterQueryRecord(ray.o, its));

        // The same two dimensions at every hit, whichever branch uses them (so that a
        // low-discrepancy sampler's dimensions mean the same thing in every sample).
        const float u = sampler->next1D();
        const Point2f sample = sampler->next2D();
        const BSDF *bsdf = its.shape->getBSDF();
        const Vector3f wiLocal = its.toLocal(-ray.d);
        if (bsdf->isDiffuse())
            return radiance + sampleDirectLight(scene, its, *bsdf, wiLocal, false, u, sample);
        // Specular: follow the sampled direction with probability 0.95.
        constexpr float kContinue = 0.95f;
        if (u >= kContinue)
            return radiance;
        BSDFQueryRecord bRec(its, wiLocal);
        const Color3f weight = bsdf->sample(bRec, sample);
        if ((weight == 0.0f).all() || !its.sidesAgree(its.toWorld(bRec.wo)))
            return radiance;
        return radiance +
               weight * Li(scene, sampler, spawnScatteredRay(its, ray, bRec)) / kContinue;
    }

    std::string toString() const override { return "WhittedIntegrator[]"; }
};

NORI_REGISTER_CLASS(WhittedIntegrator, "whitted");

} // namespace
} // namespace nori
