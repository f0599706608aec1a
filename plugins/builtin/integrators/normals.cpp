/*
 * normals — shows the shading normal of the first hit as |n| per channel (Nori's
 * first assignment's convention); black where the ray escapes.
 *
 * No parameters.
 *
 *   <integrator type="normals"/>
 */
#include <nori/integrator.h>
#include <nori/scene.h>

namespace nori {
namespace {

class NormalIntegrator : public Integrator {
public:
    explicit NormalIntegrator(const PropertyList &props) { (void)props; }

    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const override {
        (void)sampler;
        Intersection its;
        if (!scene->rayIntersect(ray, its))
            return Color3f(0.0f);
        const Normal3f n = its.shFrame.n.cwiseAbs();
        return Color3f(n.x(), n.y(), n.z());
    }

    std::string toString() const override { return "NormalIntegrator[]"; }
};

NORI_REGISTER_CLASS(NormalIntegrator, "normals");

} // namespace
} // namespace nori
