/*
 * ao — ambient occlusion: the cosine-weighted fraction of the hemisphere above the
 * first hit that is unoccluded within `length`, (1/π) ∫ V(x, ω) cos θ dω. With
 * cosine-weighted directions the estimator is the mean visibility.
 *
 * Parameters:
 *   length       float    unbounded  occluders farther than this are ignored
 *   sampleCount  integer  1          occlusion rays per camera sample
 *
 *   <integrator type="ao">
 *       <float name="length" value="0.5"/>
 *   </integrator>
 */
#include <nori/integrator.h>
#include <nori/sampler.h>
#include <nori/scene.h>
#include <nori/warp.h>

namespace nori {
namespace {

class AmbientOcclusionIntegrator : public Integrator {
public:
    explicit AmbientOcclusionIntegrator(const PropertyList &props) {
        m_length = props.getFloat("length", kInfinity);
        m_sampleCount = props.getInteger("sampleCount", 1);
        if (!(m_length > 0.0f))
            throw NoriException("ao: 'length' must be positive, got {}", m_length);
        if (m_sampleCount <= 0)
            throw NoriException("ao: 'sampleCount' must be positive, got {}", m_sampleCount);
    }

    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const override {
        Intersection its;
        if (!scene->rayIntersect(ray, its))
            return Color3f(0.0f);
        // Shade the side the camera sees.
        Frame frame = its.shFrame;
        if (frame.n.dot(ray.d) > 0.0f)
            frame = Frame(-frame.s, frame.t, -frame.n);
        int unoccluded = 0;
        for (int i = 0; i < m_sampleCount; ++i) {
            Vector3f direction = frame.toWorld(Warp::squareToCosineHemisphere(sampler->next2D()));
            Ray3f shadowRay = its.spawnRay(direction);
            shadowRay.maxt = m_length;
            if (!scene->rayIntersect(shadowRay))
                ++unoccluded;
        }
        return Color3f(static_cast<float>(unoccluded) / static_cast<float>(m_sampleCount));
    }

    std::string toString() const override {
        return fmt::format("AmbientOcclusionIntegrator[length={}, sampleCount={}]", m_length,
                           m_sampleCount);
    }

private:
    float m_length;
    int m_sampleCount;
};

NORI_REGISTER_CLASS(AmbientOcclusionIntegrator, "ao");

} // namespace
} // namespace nori
