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
#include <nori/camera.h>
#include <nori/emitter.h>
#include <nori/pathtracing.h>
#include <nori/sampler.h>
#include <nori/scene.h>
#include <nori/shading.h>

#include <algorithm>

namespace nori {
namespace {

class LightTracer : public Integrator {
public:
    explicit LightTracer(const PropertyList &props)
        : m_depth(PathDepth::read(props, "lighttracer")) {}

    void preprocess(const Scene *scene) override {
        const Camera *camera = scene->getCamera();
        if (!camera->canConnect())
            throw NoriException("lighttracer: the camera '{}' cannot be connected to from the "
                                "scene (its rays pass a lens system); use perspective or "
                                "thinlens",
                                camera->pluginName());
        const auto &shapes = scene->getShapes();
        if (camera->getMedium() || std::any_of(shapes.begin(), shapes.end(), [](const auto &shape) {
                return shape->hasMediumInterface();
            }))
            throw NoriException("lighttracer: the scene has participating media, which light "
                                "tracing does not render; use volpath");
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
        float emitterSample = sampler.next1D(), pmf = 0.0f;
        const Point2f positionSample = sampler.next2D();
        const Point2f directionSample = sampler.next2D();
        const Emitter *emitter = scene.sampleEmitter(emitterSample, pmf);
        if (!emitter || pmf == 0.0f)
            return;
        // The path's flux: Le·|cos θ|/(pdf_A·pdf_ω) over the light's pmf, whose mean is the
        // scene's total power; `throughput` is its share still carried (for the roulette).
        Ray3f ray;
        const Color3f power = emitter->samplePhoton(ray, positionSample, directionSample) / pmf;
        if (!power.isValid() || (power == 0.0f).all())
            return;
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
            if (m_depth.mayScatter(events - 1))
                connectToCamera(scene, its, toLight, power * throughput, lensSample, splats);
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

    /// Splats the light that `flux`, arriving at `its` from toLight, sends to the camera.
    static void connectToCamera(const Scene &scene, const Intersection &its,
                                const Vector3f &toLight, const Color3f &flux,
                                const Point2f &lensSample, std::vector<Splat> &splats) {
        CameraConnection camera;
        if (!scene.getCamera()->connect(its.p, lensSample, camera))
            return;
        // Where the shape's textures are filtered over the pixel footprint, the point is
        // shaded as the camera ray through that pixel shades it, with that ray's
        // differentials (raydifferential.h), so that the camera and the light paths see
        // the same surface (a filtered normal map is not the mean of its normals). That
        // ray also tests the visibility: it must find this point again.
        Intersection seen;
        const Intersection *shading = &its;
        if (usesFootprint(*its.shape)) {
            Ray3f cameraRay;
            if ((scene.sampleCameraRay(cameraRay, camera.filmPosition, lensSample) == 0.0f).all() ||
                !scene.rayIntersect(cameraRay, seen) || seen.shape != its.shape ||
                (seen.p - its.p).norm() > kSamePoint * camera.distance || !seen.sidesAgree(toLight))
                return;
            shading = &seen;
        }
        // f for light arriving along toLight and leaving toward the camera: in the
        // BSDF's convention wi is the direction toward the camera.
        const BSDFQueryRecord query(*shading, shading->toLocal(camera.direction),
                                    shading->toLocal(toLight), ESolidAngle);
        const Color3f f = shading->shape->getBSDF()->eval(query);
        const float cosLightGeometric = std::abs(toLight.dot(its.geoFrame.n));
        if ((f == 0.0f).all() || cosLightGeometric == 0.0f)
            return;
        // The particle's flux crossed the geometric surface; the BSDF weighs the light by
        // the shading cosine, and the camera sees the point's geometric projected area
        // (Veach 1997, §5.3: radiance = flux·f·|ωL·ns|/|ωL·ng| per projected area).
        const Color3f value = flux * f * std::abs(Frame::cosTheta(query.wo)) *
                              std::abs(camera.direction.dot(its.geoFrame.n)) / cosLightGeometric *
                              camera.importance;
        if ((value == 0.0f).all())
            return;
        if (shading == &its && scene.rayIntersect(its.spawnRayTo(camera.lensPoint)))
            return;
        splats.push_back({camera.filmPosition, value});
    }

    /// How far (relative to its distance from the lens) the camera ray's hit may lie from
    /// the point it was aimed at and still be that point: the film position's rounding
    /// moves it by about 1e-7 of the distance.
    static constexpr float kSamePoint = 1e-4f;

    PathDepth m_depth;
};

NORI_REGISTER_CLASS(LightTracer, "lighttracer");

} // namespace
} // namespace nori
