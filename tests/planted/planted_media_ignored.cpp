/*
 * planted_media_ignored — a negative control: an integrator that says it renders
 * participating media (handlesMedia) but traces paths as path_mis does, through the media
 * as if they were not there: a student's volumetric path tracer whose medium lookup never
 * finds the medium. On scenes without media it is path_mis; the integrator test must fail
 * it on the scene with media, against volpath.
 *
 * No parameters.
 *
 *   <integrator type="planted_media_ignored"/>
 */
#include <nori/integrator.h>
#include <nori/proplist.h>

namespace nori {

class PlantedMediaIgnored : public Integrator {
public:
    explicit PlantedMediaIgnored(const PropertyList &)
        : m_surfaces(std::static_pointer_cast<Integrator>(NoriObjectFactory::createInstance(
              "path_mis", NoriObject::EIntegrator, PropertyList()))) {}

    bool handlesMedia() const override { return true; }
    void preprocess(const Scene *scene) override { m_surfaces->preprocess(scene); }
    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const override {
        return m_surfaces->Li(scene, sampler, ray);
    }
    std::string toString() const override { return "PlantedMediaIgnored[]"; }

private:
    std::shared_ptr<Integrator> m_surfaces;
};

NORI_REGISTER_CLASS(PlantedMediaIgnored, "planted_media_ignored");

} // namespace nori
