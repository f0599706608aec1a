/*
 * material — the BSDF value at the first hit, f(wi, wo) with wi = −d (the direction back
 * along the camera ray) and wo = the shading normal (0, 0, 1), both in the hit's shading
 * frame, looked up at the hit's uv (so textures show): ETH's 2024 first-assignment
 * integrator, for checking materials and textures without lights. Black where the ray
 * escapes; no cosine and no light, so a diffuse albedo ρ shows as ρ/π.
 *
 * No parameters.
 *
 *   <integrator type="material"/>
 */
#include <nori/bsdf.h>
#include <nori/integrator.h>
#include <nori/scene.h>

namespace nori {
namespace {

class MaterialIntegrator : public Integrator {
public:
    explicit MaterialIntegrator(const PropertyList &props) { (void)props; }

    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const override {
        (void)sampler;
        Intersection its;
        if (!scene->rayIntersect(ray, its) || !its.shape->getBSDF())
            return Color3f(0.0f);
        const Vector3f wi = its.toLocal(-ray.d).normalized();
        const BSDFQueryRecord bRec(its, wi, Vector3f(0.0f, 0.0f, 1.0f), ESolidAngle);
        return its.shape->getBSDF()->eval(bRec);
    }

    std::string toString() const override { return "MaterialIntegrator[]"; }
};

NORI_REGISTER_CLASS(MaterialIntegrator, "material");

} // namespace
} // namespace nori
