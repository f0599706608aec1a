#include <nori/integrator.h>
#include <nori/scene.h>
#include <nori/bsdf.h>
#include <nori/sampler.h>
#include <nori/warp.h>

NORI_NAMESPACE_BEGIN

/* Light reflected once from a uniform white sky of radiance 1, estimated with uniform
   hemisphere sampling and shadow rays through the acceleration structure (Nori 2 style).
   A convex object with BSDF f reflects its albedo: the integral of f cos over the
   hemisphere. */
class FurnaceIntegrator : public Integrator {
public:
    FurnaceIntegrator(const PropertyList &props) {
        m_skyRadiance = props.getFloat("radiance", 1.0f);
    }

    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const {
        Intersection its;
        if (!scene->getAccel()->rayIntersect(ray, its, false))
            return Color3f(0.0f);

        const BSDF *bsdf = its.mesh->getBSDF();
        Vector3f wo = Warp::squareToUniformHemisphere(sampler->next2D());
        float pdf = Warp::squareToUniformHemispherePdf(wo);

        /* Shadow ray toward the sky */
        Ray3f shadowRay(its.p, its.toWorld(wo), Epsilon, std::numeric_limits<float>::infinity());
        Intersection blocker;
        if (scene->getAccel()->rayIntersect(shadowRay, blocker, true))
            return 0.0f;

        BSDFQueryRecord bRec(its.toLocal(-ray.d), wo, ESolidAngle);
        Color3f f = bsdf->eval(bRec);
        return f * m_skyRadiance * Frame::cosTheta(wo) / pdf;
    }

    std::string toString() const {
        return tfm::format("FurnaceIntegrator[radiance=%f]", m_skyRadiance);
    }
private:
    float m_skyRadiance;
};

NORI_REGISTER_CLASS(FurnaceIntegrator, "nori2_furnace");
NORI_NAMESPACE_END
