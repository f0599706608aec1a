/*
 * planted_mis_pmf — a negative control: a student's path tracer with MIS whose weight
 * for emission found by BSDF sampling forgets the light-selection probability (it uses
 * the light's own density where next-event estimation's is pmf × that density). With one
 * light the pmf is 1 and the image is bit-identical to path_mis; with lights of unequal
 * power it is biased, and the integrator test must say so on that scene.
 *
 * No parameters.
 *
 *   <integrator type="planted_mis_pmf"/>
 */
#include <nori/bsdf.h>
#include <nori/emitter.h>
#include <nori/pathtracing.h>
#include <nori/raydifferential.h>
#include <nori/sampler.h>
#include <nori/scene.h>

namespace nori {

class PlantedMisPmf : public Integrator {
public:
    explicit PlantedMisPmf(const PropertyList &) {}

    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &cameraRay) const override {
        Color3f radiance(0.0f), throughput(1.0f);
        Ray3f ray = cameraRay;
        bool specularBounce = true;
        float bsdfPdf = 0.0f;
        Point3f previous = ray.o;
        for (int depth = 0;; ++depth) {
            Intersection its;
            if (!scene->rayIntersect(ray, its)) {
                for (const Emitter *emitter : scene->getInfiniteEmitters())
                    radiance +=
                        throughput * found(*emitter, EmitterQueryRecord(ray, specularBounce),
                                           specularBounce, bsdfPdf);
                break;
            }
            if (const Emitter *emitter = its.shape->getEmitter())
                radiance += throughput * found(*emitter, EmitterQueryRecord(previous, its),
                                               specularBounce, bsdfPdf);
            const float emitterSample = sampler->next1D();
            const Point2f lightSample = sampler->next2D();
            const Point2f bsdfSample = sampler->next2D();
            const float rouletteSample = sampler->next1D();
            const BSDF *bsdf = its.shape->getBSDF();
            const Vector3f wiLocal = its.toLocal(-ray.d);
            if (bsdf->isDiffuse())
                radiance += throughput * sampleDirectLight(scene, its, *bsdf, wiLocal, true,
                                                           emitterSample, lightSample);
            BSDFQueryRecord bRec(its, wiLocal);
            const Color3f weight = bsdf->sample(bRec, bsdfSample);
            if ((weight == 0.0f).all() || !its.sidesAgree(its.toWorld(bRec.wo)))
                break;
            specularBounce = bRec.measure == EDiscrete || !bsdf->isDiffuse();
            bsdfPdf = bRec.measure == EDiscrete ? 0.0f : bsdf->pdf(bRec);
            throughput *= weight;
            previous = its.p;
            ray = spawnScatteredRay(its, ray, bRec);
            if (!russianRoulette(depth + 1, 3, throughput, rouletteSample))
                break;
        }
        return radiance;
    }

    std::string toString() const override { return "PlantedMisPmf[]"; }

private:
    static Color3f found(const Emitter &emitter, const EmitterQueryRecord &lRec, bool specular,
                         float bsdfPdf) {
        Color3f le = emitter.eval(lRec);
        if (specular || (le == 0.0f).all())
            return le;
        return le * balanceHeuristic(bsdfPdf, emitter.pdf(lRec)); // the planted bug: no pmf
    }
};

NORI_REGISTER_CLASS(PlantedMisPmf, "planted_mis_pmf");

} // namespace nori
