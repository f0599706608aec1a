/*
 * point — an isotropic point light. Give either its power Φ or its intensity
 * I = Φ/(4π); the irradiance at distance d, facing it, is I/d².
 *
 * Parameters:
 *   position   point  (0, 0, 0)  where the light is
 *   power      color  —          emitted power Φ (W)
 *   intensity  color  —          radiant intensity I (W/sr)
 *
 *   <emitter type="point"><point name="position" value="0, 2, 0"/>
 *       <color name="power" value="100, 100, 100"/></emitter>
 */
#include <nori/emitter.h>
#include <nori/warp.h>

namespace nori {
namespace {

class PointLight : public Emitter {
public:
    explicit PointLight(const PropertyList &props) {
        m_position = props.getPoint("position", Point3f(0.0f));
        m_intensity = readIntensity(props, "point", 4.0f * kPi);
    }

    Color3f sample(EmitterQueryRecord &lRec, const Point2f &) const override {
        // The irradiance facing the light: I/d².
        const float distanceSquared = aimAtPoint(lRec, m_position);
        return distanceSquared > 0.0f ? Color3f(m_intensity / distanceSquared) : Color3f(0.0f);
    }

    // Directions uniform over the sphere (pdf 1/4π): every photon carries 4π·I.
    Color3f sampleEmission(EmissionSample &emission, const Point2f &,
                           const Point2f &directionSample) const override {
        const Vector3f direction = Warp::squareToUniformSphere(directionSample);
        emission.ray = Ray3f(m_position, direction, 0.0f, kInfinity);
        emission.p = m_position;
        emission.density = emissionDensity(m_position, emission.n, direction);
        return m_intensity * (4.0f * kPi);
    }

    EmissionDensity emissionDensity(const Point3f &, const Normal3f &,
                                    const Vector3f &direction) const override {
        return {1.0f, Warp::squareToUniformSpherePdf(direction)};
    }

    Color3f eval(const EmitterQueryRecord &) const override { return Color3f(0.0f); }
    float pdf(const EmitterQueryRecord &) const override { return 0.0f; }
    bool isDelta() const override { return true; }
    Color3f getPower() const override { return m_intensity * (4.0f * kPi); }
    // A point that emits in every direction (θo = π, θe = π/2).
    std::optional<LightBounds> lightBounds() const override {
        LightBounds bounds;
        bounds.bounds = BoundingBox3f(m_position);
        bounds.cosThetaO = -1.0f;
        bounds.cosThetaE = 0.0f;
        bounds.phi = kPi * m_intensity.getLuminance();
        return bounds;
    }

    std::string toString() const override {
        return fmt::format("PointLight[position=({}, {}, {}), intensity=({}, {}, {})]",
                           m_position.x(), m_position.y(), m_position.z(), m_intensity.r(),
                           m_intensity.g(), m_intensity.b());
    }

private:
    Point3f m_position;
    Color3f m_intensity;
};

NORI_REGISTER_CLASS(PointLight, "point");

} // namespace
} // namespace nori
