/*
 * simple — direct light from one point light on diffuse white surfaces (Nori's
 * second assignment): L = Φ/(4π²) · max(0, cos θ)/‖x − p‖² · V(x, p).
 *
 * Parameters:
 *   position  point  (required)  position of the light
 *   energy    color  (required)  power Φ of the light
 *
 *   <integrator type="simple">
 *       <point name="position" value="-20, 40, 20"/>
 *       <color name="energy" value="3.76e4, 3.76e4, 3.76e4"/>
 *   </integrator>
 */
#include <nori/integrator.h>
#include <nori/scene.h>

namespace nori {
namespace {

class SimpleIntegrator : public Integrator {
public:
    explicit SimpleIntegrator(const PropertyList &props) {
        m_position = props.getPoint("position");
        m_energy = props.getColor("energy");
    }

    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const override {
        (void)sampler;
        Intersection its;
        if (!scene->rayIntersect(ray, its))
            return Color3f(0.0f);
        const Vector3f toLight = m_position - its.p;
        const float distanceSquared = toLight.squaredNorm();
        const float cosTheta = its.shFrame.n.dot(toLight) / std::sqrt(distanceSquared);
        if (cosTheta <= 0.0f || scene->rayIntersect(its.spawnRayTo(m_position)))
            return Color3f(0.0f);
        // A diffuse white surface (BRDF 1/π) lit by a point light of intensity Φ/(4π).
        return m_energy * (kInvFourPi * kInvPi * cosTheta / distanceSquared);
    }

    std::string toString() const override {
        return fmt::format("SimpleIntegrator[position=({}, {}, {}), energy=({}, {}, {})]",
                           m_position.x(), m_position.y(), m_position.z(), m_energy.r(),
                           m_energy.g(), m_energy.b());
    }

private:
    Point3f m_position;
    Color3f m_energy;
};

NORI_REGISTER_CLASS(SimpleIntegrator, "simple");

} // namespace
} // namespace nori
