/*
 * volpath — volumetric path tracing: path_mis with participating media (PBR 3rd ed.
 * §15.3; PBR 4th ed. §14.2). In a medium the next interaction is found by free-flight
 * sampling (analytic in homogeneous media, delta tracking in heterogeneous ones); at a
 * collision the path scatters by the phase function, with next-event estimation and
 * phase sampling combined by the balance heuristic (Veach 1997, ch. 9). Shadow rays
 * carry the transmittance of every medium they cross and pass through index-matched
 * boundaries (`null` BSDFs). The MIS weights use directional densities only, which keeps
 * each strategy unbiased (PBR 3rd ed. §15.3.1). Surfaces are treated as path_mis does.
 *
 * Parameters:
 *   maxDepth       integer  -1       scattering events (surface or medium) after the camera
 *                                    ray (-1: unbounded)
 *   rrDepth        integer  3        Russian roulette from this event on
 *   transmittance  string   "ratio"  shadow-ray estimator: "delta", "ratio" or "raymarch"
 *   stepSize       float    (required with raymarch)  ray-marching step, in world units
 *   singleScatter  boolean  false    light scatters at most once in a medium: the path ends
 *                                    at its first medium collision, lit by next-event estimation
 *
 *   <integrator type="volpath"><string name="transmittance" value="ratio"/>
 *       <integer name="maxDepth" value="32"/></integrator>
 */
#include <nori/bsdf.h>
#include <nori/camera.h>
#include <nori/emitter.h>
#include <nori/hash.h>
#include <nori/medium.h>
#include <nori/pathtracing.h>
#include <nori/phase.h>
#include <nori/raydifferential.h>
#include <nori/sampler.h>
#include <nori/scene.h>

#include <cstring>

namespace nori {
namespace {

class VolumetricPathTracer : public Integrator {
public:
    explicit VolumetricPathTracer(const PropertyList &props)
        : m_depth(PathDepth::read(props, "volpath")) {
        const std::string estimator = props.getString("transmittance", "ratio");
        if (estimator == "delta") {
            m_estimator = TransmittanceEstimator::Delta;
        } else if (estimator == "ratio") {
            m_estimator = TransmittanceEstimator::Ratio;
        } else if (estimator == "raymarch") {
            m_estimator = TransmittanceEstimator::RayMarch;
            if (!props.has("stepSize"))
                throw NoriException("volpath: 'stepSize' (world units) is required with "
                                    "transmittance = \"raymarch\"");
            m_stepSize = props.getFloat("stepSize");
            if (!(m_stepSize > 0.0f) || !std::isfinite(m_stepSize))
                throw NoriException("volpath: 'stepSize' must be positive, got {}", m_stepSize);
        } else {
            throw NoriException("volpath: 'transmittance' must be \"delta\", \"ratio\" or "
                                "\"raymarch\", got '{}'",
                                estimator);
        }
        m_singleScatter = props.getBoolean("singleScatter", false);
    }

    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &cameraRay) const override {
        // The tracking loops take as many random numbers as they need from a generator
        // seeded by one sampler dimension, so a pixel's samples stay a pure function of
        // (seed, pixel, index) (as in pbrt-v4's volpath).
        PCG32 rng = seededGenerator(sampler->next1D());
        Color3f radiance(0.0f), throughput(1.0f);
        Ray3f ray = cameraRay;
        const Medium *medium = scene->getCamera()->getMedium();
        bool specularBounce = true; // the camera "bounce": emission seen directly counts fully
        float scatterPdf = 0.0f;    // density of the direction of `ray`, for MIS
        Point3f previous = ray.o;
        Normal3f previousNormal = Normal3f::Zero(); // zero at a medium vertex
        int nullCrossings = 0;
        for (int depth = 0;;) {
            Intersection its;
            const bool hit = scene->rayIntersect(ray, its);

            if (medium) {
                Ray3f segment(ray.o, ray.d, ray.mint, hit ? its.t : kInfinity);
                const MediumSample mRec = medium->sampleFreeFlight(segment, rng);
                throughput *= mRec.weight;
                if ((throughput <= 0.0f).all())
                    break;
                if (mRec.scattered) {
                    if (!m_depth.mayScatter(depth))
                        break;
                    const float emitterSample = sampler->next1D();
                    const Point2f lightSample = sampler->next2D();
                    const Point2f phaseSample = sampler->next2D();
                    const float rouletteSample = sampler->next1D();
                    const PhaseFunction &phase = *medium->getPhaseFunction();
                    const Vector3f wi = -ray.d;
                    radiance += throughput * lightAtMediumPoint(scene, mRec.p, medium, phase, wi,
                                                                emitterSample, lightSample, rng);
                    if (m_singleScatter)
                        break;
                    PhaseFunctionQueryRecord pRec(wi);
                    const Color3f weight = phase.sample(pRec, phaseSample);
                    if ((weight == 0.0f).all())
                        break;
                    throughput *= weight;
                    specularBounce = false;
                    scatterPdf = phase.pdf(pRec);
                    previous = mRec.p;
                    previousNormal = Normal3f::Zero();
                    ray = Ray3f(mRec.p, pRec.wo, 0.0f, kInfinity);
                    nullCrossings = 0;
                    if (!russianRoulette(++depth, m_depth.rrDepth, throughput, rouletteSample))
                        break;
                    continue;
                }
            }

            if (!hit) {
                for (const Emitter *emitter : scene->getInfiniteEmitters())
                    radiance +=
                        throughput * emissionWithMIS(scene, *emitter,
                                                     EmitterQueryRecord(ray, specularBounce),
                                                     previousNormal, specularBounce, scatterPdf);
                break;
            }
            if (const Emitter *emitter = its.shape->getEmitter())
                radiance +=
                    throughput * emissionWithMIS(scene, *emitter, EmitterQueryRecord(previous, its),
                                                 previousNormal, specularBounce, scatterPdf);

            const BSDF *bsdf = its.shape->getBSDF();
            const Vector3f wiLocal = its.toLocal(-ray.d);
            if (bsdf->isNull()) {
                // An index-matched boundary: the ray goes on into the medium behind it,
                // and the last real vertex stays the one MIS refers to.
                if (++nullCrossings > kMaxNullCrossings)
                    break;
                medium = mediumBehind(its, ray.d, medium);
                BSDFQueryRecord bRec(its, wiLocal);
                bsdf->sample(bRec, Point2f(0.5f, 0.5f));
                ray = spawnScatteredRay(its, ray, bRec);
                continue;
            }

            if (!m_depth.mayScatter(depth))
                break;
            // The same dimensions in the same order as path_mis draws them.
            const float emitterSample = sampler->next1D();
            const Point2f lightSample = sampler->next2D();
            const Point2f bsdfSample = sampler->next2D();
            const float rouletteSample = sampler->next1D();

            if (bsdf->isDiffuse())
                radiance += throughput *
                            sampleDirectLight(
                                scene, its, *bsdf, wiLocal, true, emitterSample, lightSample,
                                [&](const Ray3f &shadowRay, const Vector3f &toLight) {
                                    return transmittanceAlong(
                                        scene, shadowRay, mediumBehind(its, toLight, medium), rng);
                                });

            BSDFQueryRecord bRec(its, wiLocal);
            const Color3f weight = bsdf->sample(bRec, bsdfSample);
            const Vector3f wo = its.toWorld(bRec.wo);
            if ((weight == 0.0f).all() || !its.sidesAgree(wo))
                break;
            specularBounce = bRec.measure == EDiscrete || !bsdf->isDiffuse();
            scatterPdf = bRec.measure == EDiscrete ? 0.0f : bsdf->pdf(bRec);
            throughput *= weight;
            previous = its.p;
            previousNormal = its.shFrame.n;
            medium = mediumBehind(its, wo, medium);
            ray = spawnScatteredRay(its, ray, bRec);
            nullCrossings = 0;
            if (!russianRoulette(++depth, m_depth.rrDepth, throughput, rouletteSample))
                break;
        }
        return radiance;
    }

    bool handlesMedia() const override { return true; }

    std::string toString() const override {
        static const char *names[] = {"delta", "ratio", "raymarch"};
        return fmt::format("VolumetricPathTracer[maxDepth={}, rrDepth={}, transmittance={}{}, "
                           "singleScatter={}]",
                           m_depth.maxDepth, m_depth.rrDepth, names[int(m_estimator)],
                           m_estimator == TransmittanceEstimator::RayMarch
                               ? fmt::format(" (stepSize={})", m_stepSize)
                               : "",
                           m_singleScatter);
    }

private:
    /// A path stuck between coincident null surfaces is ended after this many crossings.
    static constexpr int kMaxNullCrossings = 256;

    static PCG32 seededGenerator(float sample) {
        uint32_t bits;
        std::memcpy(&bits, &sample, sizeof(bits));
        return PCG32(hashValues(bits), hashValues(bits, 1));
    }

    /// The medium a ray leaving the surface in direction d travels in: the one on that
    /// side when the shape bounds media, else the one the ray was in.
    static const Medium *mediumBehind(const Intersection &its, const Vector3f &d,
                                      const Medium *current) {
        if (!its.shape->hasMediumInterface())
            return current;
        return its.shape->getMediumInterface().toward(d, its.geoFrame.n);
    }

    /// The transmittance along `ray` (unit direction, ending short of the light) from a
    /// point in `medium`: the product over the media it crosses, through index-matched
    /// boundaries; zero when any other surface blocks it.
    Color3f transmittanceAlong(const Scene *scene, Ray3f ray, const Medium *medium,
                               PCG32 &rng) const {
        Color3f transmittance(1.0f);
        const Point3f target = ray(ray.maxt);
        for (int crossing = 0; crossing <= kMaxNullCrossings; ++crossing) {
            Intersection its;
            const bool hit = scene->rayIntersect(ray, its);
            if (medium) {
                const Ray3f segment(ray.o, ray.d, ray.mint, hit ? its.t : ray.maxt);
                transmittance *= medium->transmittance(segment, rng, m_estimator, m_stepSize);
                if ((transmittance <= 0.0f).all())
                    return Color3f(0.0f);
            }
            if (!hit)
                return transmittance;
            if (!its.shape->getBSDF()->isNull())
                return Color3f(0.0f);
            medium = mediumBehind(its, ray.d, medium);
            ray = its.spawnRayTo(target);
        }
        return Color3f(0.0f);
    }

    /// Next-event estimation at a collision in `medium`, weighted against phase sampling
    /// by the balance heuristic (not in single-scattering mode, where nothing continues
    /// the path).
    Color3f lightAtMediumPoint(const Scene *scene, const Point3f &p, const Medium *medium,
                               const PhaseFunction &phase, const Vector3f &wi, float emitterSample,
                               const Point2f &sample, PCG32 &rng) const {
        float u = emitterSample, pmf;
        const Emitter *emitter = scene->sampleEmitter(p, Normal3f::Zero(), u, pmf);
        if (!emitter || pmf == 0.0f)
            return Color3f(0.0f);
        EmitterQueryRecord lRec(p);
        const Color3f radianceOverPdf = emitter->sample(lRec, sample) / pmf;
        if ((radianceOverPdf == 0.0f).all())
            return Color3f(0.0f);
        const PhaseFunctionQueryRecord pRec(wi, lRec.wi, ESolidAngle);
        const Color3f f = phase.eval(pRec);
        if ((f == 0.0f).all())
            return Color3f(0.0f);
        const float distance = (lRec.p - p).norm();
        const Color3f transmittance = transmittanceAlong(
            scene, Ray3f(p, lRec.wi, 0.0f, distance * (1.0f - kShadowEpsilon)), medium, rng);
        float weight = 1.0f;
        if (!m_singleScatter && !emitter->isDelta()) {
            const float lightPdf = pmf * lRec.pdf;
            weight = balanceHeuristic(lightPdf, phase.pdf(pRec));
        }
        return f * radianceOverPdf * transmittance * weight;
    }

    PathDepth m_depth;
    TransmittanceEstimator m_estimator = TransmittanceEstimator::Ratio;
    float m_stepSize = 0.0f;
    bool m_singleScatter;
};

NORI_REGISTER_CLASS(VolumetricPathTracer, "volpath");

} // namespace
} // namespace nori
