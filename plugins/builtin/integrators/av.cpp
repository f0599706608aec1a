/*
 * av — average visibility (the ETH course's exercise): 1 where the camera ray escapes;
 * at a hit, 1 if a uniformly sampled direction in the hemisphere about the normal is
 * unoccluded within `length`, else 0. Its mean is the fraction of the hemisphere that
 * is open.
 *
 * Parameters:
 *   length  float  (required)  how far occluders count
 *
 *   <integrator type="av"><float name="length" value="10"/></integrator>
 */
#include <nori/integrator.h>
#include <nori/sampler.h>
#include <nori/scene.h>
#include <nori/warp.h>

namespace nori {
namespace {

class AverageVisibility : public Integrator {
public:
    explicit AverageVisibility(const PropertyList &props) {
        m_length = props.getFloat("length");
        if (!(m_length > 0.0f))
            throw NoriException("av: 'length' must be positive, got {}", m_length);
    }

    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const override {
        Intersection its;
        if (!scene->rayIntersect(ray, its))
            return Color3f(1.0f);
        // The hemisphere on the side the ray came from.
        Vector3f local = Warp::squareToUniformHemisphere(sampler->next2D());
        if (its.shFrame.n.dot(ray.d) > 0.0f)
            local.z() = -local.z();
        Ray3f shadowRay = its.spawnRay(its.shFrame.toWorld(local));
        shadowRay.maxt = m_length;
        return Color3f(scene->rayIntersect(shadowRay) ? 0.0f : 1.0f);
    }

    std::string toString() const override {
        return fmt::format("AverageVisibility[length={}]", m_length);
    }

private:
    float m_length;
};

NORI_REGISTER_CLASS(AverageVisibility, "av");

} // namespace
} // namespace nori
