/*
 * direct — direct lighting (Veach 1997, ch. 9; PBR 4th ed. §13.4). The emission seen
 * from the camera plus light that reaches the first surface straight from an emitter
 * and scatters once toward the camera. `direct` and `direct_ems` (the ETH course's two
 * names) sample the emitters (next-event estimation); `direct_mats` samples the BSDF
 * and counts the emitters its ray hits; `direct_mis` does both and weights them by
 * multiple importance sampling (balance heuristic). Emitters seen through a delta lobe
 * (a mirror) count with every strategy. It is `path` stopped after one bounce, and
 * draws the same samples, so `direct_mis` and `path_mis` with maxDepth 1 give the same
 * image.
 *
 * No parameters (one bounce: emission seen directly plus light scattered once).
 *
 * Also registered as: direct_ems, direct_mats, direct_mis.
 *
 *   <integrator type="direct"/>
 *
 *   <integrator type="direct_ems"/>
 *
 *   <integrator type="direct_mats"/>
 *
 *   <integrator type="direct_mis"/>
 */
#include <nori/bsdf.h>
#include <nori/emitter.h>
#include <nori/pathtracing.h>
#include <nori/raydifferential.h>
#include <nori/sampler.h>
#include <nori/scene.h>

namespace nori {
namespace {

class DirectLighting : public Integrator {
public:
    /// How the light of the one bounce is found (see the doc comment).
    enum class Strategy { EmitterSampling, BSDFSampling, MIS };

    DirectLighting(Strategy strategy, std::string name)
        : m_strategy(strategy), m_name(std::move(name)) {}
    explicit DirectLighting(const PropertyList &)
        : DirectLighting(Strategy::EmitterSampling, "Direct") {}

    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &cameraRay) const override {
        // The emission seen from the camera counts fully.
        Color3f radiance(0.0f);
        Intersection its;
        if (!scene->rayIntersect(cameraRay, its)) {
            addLightAtInfinity(radiance, Color3f(1.0f), scene, cameraRay, Normal3f::Zero(), true,
                               0.0f);
            return radiance;
        }
        if (const Emitter *emitter = its.shape->getEmitter())
            radiance += emitter->eval(EmitterQueryRecord(cameraRay.o, its));

        const float emitterSample = sampler->next1D();
        const Point2f lightSample = sampler->next2D();
        const Point2f bsdfSample = sampler->next2D();
        sampler->next1D(); // path's Russian roulette sample, so that the dimensions line up

        // Emitter sampling, where the BSDF has a non-delta lobe for the light to meet.
        const BSDF *bsdf = its.shape->getBSDF();
        const Vector3f wiLocal = its.toLocal(-cameraRay.d);
        if (m_strategy != Strategy::BSDFSampling && bsdf->isDiffuse())
            radiance += sampleDirectLight(scene, its, *bsdf, wiLocal, m_strategy == Strategy::MIS,
                                          emitterSample, lightSample);

        // BSDF sampling: the emitter the sampled ray finds, if it counts for the strategy.
        BSDFQueryRecord bRec(its, wiLocal);
        const Color3f weight = bsdf->sample(bRec, bsdfSample);
        if ((weight == 0.0f).all() || !its.sidesAgree(its.toWorld(bRec.wo)))
            return radiance;
        const bool specular = bRec.measure == EDiscrete || !bsdf->isDiffuse();
        if (m_strategy == Strategy::EmitterSampling && !specular)
            return radiance; // emitter sampling counted this light already
        const float bsdfPdf = bRec.measure == EDiscrete ? 0.0f : bsdf->pdf(bRec);
        const Ray3f ray = spawnScatteredRay(its, cameraRay, bRec);
        Intersection next;
        if (!scene->rayIntersect(ray, next))
            addLightAtInfinity(radiance, weight, scene, ray, its.shFrame.n, specular, bsdfPdf);
        else if (const Emitter *emitter = next.shape->getEmitter())
            radiance += weight * foundEmission(scene, *emitter, EmitterQueryRecord(its.p, next),
                                               its.shFrame.n, specular, bsdfPdf);
        return radiance;
    }

    std::string toString() const override { return m_name + "[]"; }

private:
    /// The emission a ray found, weighted for the strategy: all of it after a specular
    /// bounce or with BSDF sampling alone, else the balance heuristic against emitter
    /// sampling.
    Color3f foundEmission(const Scene *scene, const Emitter &emitter,
                          const EmitterQueryRecord &lRec, const Normal3f &refNormal, bool specular,
                          float bsdfPdf) const {
        if (specular || m_strategy == Strategy::BSDFSampling)
            return emitter.eval(lRec);
        return emissionWithMIS(scene, emitter, lRec, refNormal, false, bsdfPdf);
    }

    /// Adds the lights at infinity that a ray leaving the scene sees, times `weight`.
    void addLightAtInfinity(Color3f &radiance, const Color3f &weight, const Scene *scene,
                            const Ray3f &ray, const Normal3f &refNormal, bool specular,
                            float bsdfPdf) const {
        for (const Emitter *emitter : scene->getInfiniteEmitters())
            radiance += weight * foundEmission(scene, *emitter, EmitterQueryRecord(ray, specular),
                                               refNormal, specular, bsdfPdf);
    }

    Strategy m_strategy;
    std::string m_name;
};

/// `direct_ems`: emitter sampling (as `direct`).
class DirectEMS : public DirectLighting {
public:
    explicit DirectEMS(const PropertyList &)
        : DirectLighting(Strategy::EmitterSampling, "DirectEMS") {}
};

/// `direct_mats`: BSDF sampling.
class DirectMATS : public DirectLighting {
public:
    explicit DirectMATS(const PropertyList &)
        : DirectLighting(Strategy::BSDFSampling, "DirectMATS") {}
};

/// `direct_mis`: both, weighted by multiple importance sampling.
class DirectMIS : public DirectLighting {
public:
    explicit DirectMIS(const PropertyList &) : DirectLighting(Strategy::MIS, "DirectMIS") {}
};

NORI_REGISTER_CLASS(DirectLighting, "direct");
NORI_REGISTER_ALIAS(DirectEMS, "direct_ems", ems);
NORI_REGISTER_ALIAS(DirectMATS, "direct_mats", mats);
NORI_REGISTER_ALIAS(DirectMIS, "direct_mis", mis);

} // namespace
} // namespace nori
