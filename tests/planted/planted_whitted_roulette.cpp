/*
 * planted_whitted_roulette — a negative control: a student's Whitted-style ray tracer
 * that continues at mirrors and glass with probability 0.95 but forgets to divide by it,
 * so what is seen in them is 5% too dark for every specular bounce. Diffuse surfaces in
 * view are right; the integrator test, against the built-in `whitted`, must find the
 * mirror and the glass.
 *
 * No parameters.
 *
 *   <integrator type="planted_whitted_roulette"/>
 */
#include <nori/bsdf.h>
#include <nori/emitter.h>
#include <nori/integrator.h>
#include <nori/pathtracing.h>
#include <nori/raydifferential.h>
#include <nori/sampler.h>
#include <nori/scene.h>

namespace nori {

class PlantedWhittedRoulette : public Integrator {
public:
    explicit PlantedWhittedRoulette(const PropertyList &) {}

    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const override {
        Intersection its;
        if (!scene->rayIntersect(ray, its))
            return lightAtInfinity(*scene, ray);
        Color3f radiance(0.0f);
        if (const Emitter *emitter = its.shape->getEmitter())
            radiance += emitter->eval(EmitterQueryRecord(ray.o, its));
        const float u = sampler->next1D();
        const Point2f sample = sampler->next2D();
        const BSDF *bsdf = its.shape->getBSDF();
        const Vector3f wiLocal = its.toLocal(-ray.d);
        if (bsdf->isDiffuse())
            return radiance + sampleDirectLight(scene, its, *bsdf, wiLocal, false, u, sample);
        if (u >= 0.95f)
            return radiance;
        BSDFQueryRecord bRec(its, wiLocal);
        const Color3f weight = bsdf->sample(bRec, sample);
        if ((weight == 0.0f).all() || !its.sidesAgree(its.toWorld(bRec.wo)))
            return radiance;
        // The bug: no division by the probability 0.95 of having continued.
        return radiance + weight * Li(scene, sampler, spawnScatteredRay(its, ray, bRec));
    }

    /// Not named after the course's "whitted", so it says what it estimates.
    IntegratorQuantity quantity() const override { return IntegratorQuantity::Whitted; }

    std::string toString() const override { return "PlantedWhittedRoulette[]"; }
};

NORI_REGISTER_CLASS(PlantedWhittedRoulette, "planted_whitted_roulette");

} // namespace nori
