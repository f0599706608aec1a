/*
 * directional — a distant light: parallel rays along one direction, delivering the
 * irradiance E to a surface facing them (PBR 4th ed. §12.4); a delta light in
 * direction, never hit by rays. It lights the whole scene: its power is E times the
 * area of the disk of the scene's bounding sphere, π r².
 *
 * Parameters:
 *   direction   vector  (0, −1, 0)  the direction the light travels
 *   irradiance  color   1           irradiance on a surface facing the light (W/m²)
 *
 *   <emitter type="directional"><vector name="direction" value="-1, -2, -0.5"/>
 *       <color name="irradiance" value="3, 2.8, 2.5"/></emitter>
 */
#include <nori/bbox.h>
#include <nori/emitter.h>
#include <nori/proplist.h>

namespace nori {
namespace {

class DirectionalLight : public Emitter {
public:
    explicit DirectionalLight(const PropertyList &props) {
        const Vector3f direction = props.getVector("direction", Vector3f(0.0f, -1.0f, 0.0f));
        if (!(direction.norm() > 0.0f) || !direction.allFinite())
            throw NoriException("directional: 'direction' must be a finite, non-zero vector");
        m_toLight = -direction.normalized();
        m_irradiance = props.getColor("irradiance", Color3f(1.0f));
        if ((m_irradiance < 0.0f).any() || !m_irradiance.allFinite())
            throw NoriException("directional: 'irradiance' must be finite and not negative");
    }

    void setSceneBounds(const BoundingBox3f &bounds) override { m_scene.set(bounds); }

    Color3f sample(EmitterQueryRecord &lRec, const Point2f &) const override {
        // A point beyond the scene's bounding sphere in the light's direction, so that
        // the shadow ray crosses everything that can block the light.
        lRec.wi = m_toLight;
        m_scene.placeBeyond(lRec);
        lRec.pdf = 1.0f; // a delta distribution in direction
        return m_irradiance;
    }

    // Photons cross the disk of the scene's bounding sphere facing the light, uniformly:
    // each carries E·πr².
    Color3f sampleEmission(EmissionSample &emission, const Point2f &positionSample,
                           const Point2f &) const override {
        const float diskArea = m_scene.photonRayFrom(m_toLight, positionSample, emission);
        emission.density.direction = 1.0f; // a delta distribution in direction
        return m_irradiance * diskArea;
    }

    EmissionDensity emissionDensity(const Point3f &, const Normal3f &,
                                    const Vector3f &) const override {
        return {1.0f / m_scene.diskArea(), 1.0f};
    }

    bool liesAtInfinity() const override { return true; }

    Color3f eval(const EmitterQueryRecord &) const override { return Color3f(0.0f); }
    float pdf(const EmitterQueryRecord &) const override { return 0.0f; }
    bool isDelta() const override { return true; }
    Color3f getPower() const override { return m_irradiance * m_scene.diskArea(); }

    std::string toString() const override {
        return fmt::format("DirectionalLight[toLight=({}, {}, {}), irradiance=({}, {}, {})]",
                           m_toLight.x(), m_toLight.y(), m_toLight.z(), m_irradiance.r(),
                           m_irradiance.g(), m_irradiance.b());
    }

private:
    Vector3f m_toLight;
    Color3f m_irradiance;
    SceneBoundingSphere m_scene;
};

NORI_REGISTER_CLASS(DirectionalLight, "directional");

} // namespace
} // namespace nori
