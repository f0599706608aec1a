/*
 * lighttracer — light tracing, also called particle tracing (Veach 1997, §10.2; PBR 3rd
 * ed., §16.1): each sample traces a path from a light, chosen by power, and connects every
 * surface point it reaches to the camera; the light found there lands on whichever pixel
 * sees the point (a splat), weighted by the camera's importance We. Light seen directly
 * (area lights, the environment) comes from the camera ray. It finds easily what a path
 * tracer finds only by luck: caustics on diffuse surfaces (light, glass, floor, camera).
 * It cannot render what the camera sees only through a delta BSDF: mirrors and smooth
 * glass seen directly, and whatever is seen in them, stay black, because those paths
 * have no vertex that can be connected to the lens (bdpt has). Cameras: perspective and
 * thinlens; scenes with participating media are an error.
 *
 * Parameters:
 *   maxDepth  integer  -1  scattering events of a whole path (-1: unbounded), as the path
 *                          tracers count them
 *   rrDepth   integer  3   Russian roulette from this event of the light path on
 *
 *   <integrator type="lighttracer"/>
 *
 *   <integrator type="lighttracer"><integer name="maxDepth" value="4"/></integrator>
 */
#include <nori/bsdf.h>
#include <nori/emitter.h>
#include <nori/pathtracing.h>
#include <nori/sampler.h>
#include <nori/scene.h>

namespace nori {
namespace {

class LightTracer : public Integrator {
public:
    explicit LightTracer(const PropertyList &props)
        : m_depth(PathDepth::read(props, "lighttracer")) {}

    void preprocess(const Scene *scene) override {
        requireLightPathScene(*scene, "lighttracer", "light tracing");
    }

    bool splats() const override { return true; }
    bool rendersSpecularInView() const override { return false; }

    /// The light the camera ray sees directly: an area light it hits, or the lights at
    /// infinity when it leaves the scene. Paths of one or more scattering events come
    /// from the lights, as splats (LiAndSplats).
    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const override {
        (void)sampler;
        Intersection its;
        if (!scene->rayIntersect(ray, its))
            return lightAtInfinity(*scene, ray);
        if (const Emitter *emitter = its.shape->getEmitter())
            return emitter->eval(EmitterQueryRecord(ray.o, its));
        return Color3f(0.0f);
    }

    Color3f LiAndSplats(const Scene *scene, Sampler *sampler, const Ray3f &ray,
                        std::vector<Splat> &splats) const override {
        Color3f direct = Li(scene, sampler, ray);
        traceLightPath(*scene, *sampler, splats);
        return direct;
    }

    std::string toString() const override {
        return fmt::format("LightTracer[maxDepth={}, rrDepth={}]", m_depth.maxDepth,
                           m_depth.rrDepth);
    }

private:
    /// One path from a light; each surface vertex connected to the camera.
    void traceLightPath(const Scene &scene, Sampler &sampler, std::vector<Splat> &splats) const {
        const float emitterSample = sampler.next1D();
        const Point2f positionSample = sampler.next2D();
        const Point2f directionSample = sampler.next2D();
        // The path's flux: Le·|cos θ|/(pdf_A·pdf_ω) over the light's pmf, whose mean is the
        // scene's total power; `throughput` is its share still carried (for the roulette).
        EmissionSample emission;
        const Emitter *emitter = nullptr;
        float pmf = 0.0f;
        const Color3f power = sampleLightPath(scene, emitterSample, positionSample, directionSample,
                                              emission, emitter, pmf);
        if ((power == 0.0f).all())
            return;
        Ray3f ray = emission.ray;
        Color3f throughput(1.0f);
        // Connecting the vertex reached after `events` − 1 scattering events makes a path
        // that scatters `events` times, the last time toward the camera.
        for (int events = 1;; ++events) {
            // The same dimensions in the same order at every vertex, used or not.
            const Point2f lensSample = sampler.next2D();
            const Point2f bsdfSample = sampler.next2D();
            const float rouletteSample = sampler.next1D();

            Intersection its;
            if (!scene.rayIntersect(ray, its))
                return;
            const Vector3f toLight = -ray.d.normalized();
            // The path tracers drop light arriving from a direction on which the shading
            // and geometric surfaces disagree (Intersection::sidesAgree); so does this.
            if (!its.sidesAgree(toLight))
                return;
            const BSDF &bsdf = *its.shape->getBSDF();
            if (m_depth.mayScatter(events - 1)) {
                CameraLink link;
                const Color3f value =
                    power * throughput * connectToCamera(scene, its, toLight, lensSample, link);
                if (!(value == 0.0f).all())
                    splats.push_back({link.camera.filmPosition, value});
            }
            if (!m_depth.mayScatter(events))
                return;

            // Continue with a direction the BSDF samples, weighted for flux.
            BSDFQueryRecord bRec(its, its.toLocal(toLight));
            const Color3f weight = bsdf.sample(bRec, bsdfSample);
            if ((weight == 0.0f).all())
                return;
            const Vector3f wo = its.toWorld(bRec.wo);
            const float adjoint = adjointSampleFactor(its, toLight, wo, bRec);
            if (adjoint == 0.0f)
                return;
            throughput *= weight * adjoint;
            if (!russianRoulette(events, m_depth.rrDepth, throughput, rouletteSample))
                return;
            ray = its.spawnRay(wo);
        }
    }

    PathDepth m_depth;
};

NORI_REGISTER_CLASS(LightTracer, "lighttracer");

} // namespace
} // namespace nori
