/*
 * path — unidirectional path tracing (Kajiya 1986; Veach 1997, ch. 9; PBR 4th ed.
 * §13.4). From the camera, each path bounces by sampling the BSDF at every surface it
 * hits, and gathers light in one of three ways. `path` and `path_mis` sample the
 * emitters at every vertex with a non-delta BSDF (next-event estimation) and also
 * count emitters that the BSDF-sampled rays hit, weighting the two by multiple
 * importance sampling (balance heuristic); `path_ems` counts only the emitter samples
 * (and emitters seen through delta lobes); `path_mats` counts only what the
 * BSDF-sampled rays hit. All three converge to the same image; their noise differs.
 *
 * Parameters:
 *   maxDepth  integer  -1  bounces after the camera ray (-1: unbounded)
 *   rrDepth   integer  3   Russian roulette from this bounce on
 *
 * Also registered as: path_mis, path_ems, path_mats.
 *
 *   <integrator type="path"/>
 *
 *   <integrator type="path_mis"><integer name="maxDepth" value="8"/></integrator>
 *
 *   <integrator type="path_ems"/>
 *
 *   <integrator type="path_mats"/>
 */
#include <nori/bsdf.h>
#include <nori/emitter.h>
#include <nori/pathtracing.h>
#include <nori/raydifferential.h>
#include <nori/sampler.h>
#include <nori/scene.h>

namespace nori {
namespace {

class PathTracer : public Integrator {
public:
    /// How a path gathers light (see the doc comment).
    enum class Strategy { MIS, EmitterSampling, BSDFSampling };

    PathTracer(const PropertyList &props, Strategy strategy, std::string name)
        : m_strategy(strategy), m_depth(PathDepth::read(props, name)), m_name(std::move(name)) {}
    explicit PathTracer(const PropertyList &props) : PathTracer(props, Strategy::MIS, "PathMIS") {}

    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &cameraRay) const override {
        Color3f radiance(0.0f), throughput(1.0f);
        Ray3f ray = cameraRay;
        bool specularBounce = true; // the camera "bounce": emission seen directly counts fully
        float bsdfPdf = 0.0f;       // density of the direction of `ray`, for MIS
        Point3f previous = ray.o;
        Normal3f previousNormal = Normal3f::Zero(); // its shading normal, for the light's pmf
        for (int depth = 0;; ++depth) {
            // 1. Find the next vertex; a ray that leaves the scene sees the lights at
            //    infinity (environment maps, constant backgrounds).
            Intersection its;
            if (!scene->rayIntersect(ray, its)) {
                for (const Emitter *emitter : scene->getInfiniteEmitters())
                    radiance += throughput * foundEmission(scene, *emitter,
                                                           EmitterQueryRecord(ray, specularBounce),
                                                           previousNormal, specularBounce, bsdfPdf);
                break;
            }
            // 2. Emission of the surface the ray found (an area light).
            if (const Emitter *emitter = its.shape->getEmitter())
                radiance +=
                    throughput * foundEmission(scene, *emitter, EmitterQueryRecord(previous, its),
                                               previousNormal, specularBounce, bsdfPdf);
            if (!m_depth.mayScatter(depth))
                break;

            // Every bounce draws the same dimensions in the same order, used or not, so
            // that a dimension of a low-discrepancy sampler means the same thing in every
            // sample.
            const float emitterSample = sampler->next1D();
            const Point2f lightSample = sampler->next2D();
            const Point2f bsdfSample = sampler->next2D();
            const float rouletteSample = sampler->next1D();

            // 3. Next-event estimation: a light sample, where the BSDF has a non-delta lobe
            //    for it to meet.
            const BSDF *bsdf = its.shape->getBSDF();
            const Vector3f wiLocal = its.toLocal(-ray.d);
            if (m_strategy != Strategy::BSDFSampling && bsdf->isDiffuse())
                radiance += throughput * sampleDirectLight(scene, its, *bsdf, wiLocal,
                                                           m_strategy == Strategy::MIS,
                                                           emitterSample, lightSample);

            // 4. Continue the path in a direction the BSDF samples; its weight
            //    f·|cos θ|/pdf multiplies the throughput.
            BSDFQueryRecord bRec(its, wiLocal);
            const Color3f weight = bsdf->sample(bRec, bsdfSample);
            if ((weight == 0.0f).all() || !its.sidesAgree(its.toWorld(bRec.wo)))
                break;
            specularBounce = bRec.measure == EDiscrete || !bsdf->isDiffuse();
            bsdfPdf = bRec.measure == EDiscrete ? 0.0f : bsdf->pdf(bRec);
            throughput *= weight;
            previous = its.p;
            previousNormal = its.shFrame.n;
            ray = spawnScatteredRay(its, ray, bRec);

            // 5. Russian roulette ends long paths of little throughput without bias.
            if (!russianRoulette(depth + 1, m_depth.rrDepth, throughput, rouletteSample))
                break;
        }
        return radiance;
    }

    std::string toString() const override {
        return fmt::format("{}[maxDepth={}, rrDepth={}]", m_name, m_depth.maxDepth,
                           m_depth.rrDepth);
    }

private:
    /// The emission of `emitter` that a BSDF-sampled (or camera) ray found, weighted for
    /// the strategy: all of it after a specular bounce or with BSDF sampling alone, none
    /// with emitter sampling alone (next-event estimation counted it), and the balance
    /// heuristic against emitter sampling with MIS.
    Color3f foundEmission(const Scene *scene, const Emitter &emitter,
                          const EmitterQueryRecord &lRec, const Normal3f &refNormal,
                          bool specularBounce, float bsdfPdf) const {
        if (specularBounce || m_strategy == Strategy::BSDFSampling)
            return emitter.eval(lRec);
        if (m_strategy == Strategy::EmitterSampling)
            return Color3f(0.0f);
        return emissionWithMIS(scene, emitter, lRec, refNormal, false, bsdfPdf);
    }

    Strategy m_strategy;
    PathDepth m_depth;
    std::string m_name;
};

/// `path_ems`: emitter sampling alone.
class PathEMS : public PathTracer {
public:
    explicit PathEMS(const PropertyList &props)
        : PathTracer(props, Strategy::EmitterSampling, "PathEMS") {}
};

/// `path_mats`: BSDF sampling alone.
class PathMATS : public PathTracer {
public:
    explicit PathMATS(const PropertyList &props)
        : PathTracer(props, Strategy::BSDFSampling, "PathMATS") {}
};

NORI_REGISTER_CLASS(PathTracer, "path");
NORI_REGISTER_ALIAS(PathTracer, "path_mis", mis);
NORI_REGISTER_ALIAS(PathEMS, "path_ems", ems);
NORI_REGISTER_ALIAS(PathMATS, "path_mats", mats);

} // namespace
} // namespace nori
