/*
 * planted_importance — a negative control: the built-in light tracer with a student's
 * camera importance that forgets the film's projection, the 1/cos³θ of We = 1/(A cos⁴θ)
 * times the cos θ of the lens (PBR 3rd ed., §16.1.1): every splat is multiplied back by
 * cos³θ, θ the angle of its film position from the view axis. The centre of the image is
 * right and its edges too dark, so the integrator test must fail it against path_mis.
 *
 * No parameters.
 *
 *   <integrator type="planted_importance"/>
 */
#include <nori/camera.h>
#include <nori/integrator.h>
#include <nori/proplist.h>
#include <nori/scene.h>

namespace nori {

class PlantedImportance : public Integrator {
public:
    explicit PlantedImportance(const PropertyList &)
        : m_lightTracer(std::static_pointer_cast<Integrator>(NoriObjectFactory::createInstance(
              "lighttracer", NoriObject::EIntegrator, PropertyList()))) {}

    void preprocess(const Scene *scene) override { m_lightTracer->preprocess(scene); }
    bool splats() const override { return true; }
    bool rendersSpecularInView() const override { return false; }
    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const override {
        return m_lightTracer->Li(scene, sampler, ray);
    }
    Color3f LiAndSplats(const Scene *scene, Sampler *sampler, const Ray3f &ray,
                        std::vector<Splat> &splats) const override {
        Color3f direct = m_lightTracer->LiAndSplats(scene, sampler, ray, splats);
        const Camera &camera = *scene->getCamera();
        Ray3f axis, toSplat;
        camera.sampleRay(axis, camera.getOutputSize().cast<float>() * 0.5f, Point2f(0.5f, 0.5f));
        for (Splat &splat : splats) {
            camera.sampleRay(toSplat, splat.position, Point2f(0.5f, 0.5f));
            const float cosTheta = axis.d.dot(toSplat.d);
            splat.value *= cosTheta * cosTheta * cosTheta;
        }
        return direct;
    }
    std::string toString() const override { return "PlantedImportance[]"; }

private:
    std::shared_ptr<Integrator> m_lightTracer;
};

NORI_REGISTER_CLASS(PlantedImportance, "planted_importance");

} // namespace nori
