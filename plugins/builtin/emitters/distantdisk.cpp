/*
 * distantdisk — a disk-shaped light at infinity (ETH's 2015 course, test-distant.xml): the
 * radiance L arrives from every direction within thetaA degrees of the +z axis of the
 * emitter's frame (toWorld), and from no other; thetaA = 180 makes it a constant
 * environment. Directions are sampled uniformly over that spherical cap (PBR 4th ed.
 * §A.5.6), pdf 1/(2π(1 − cos thetaA)); photons leave the disk of the scene's bounding
 * sphere facing each direction, so its power is L · 2π(1 − cos thetaA) · π r².
 *
 * Parameters:
 *   radiance  color      1         the radiance from directions inside the cap
 *   thetaA    float      5         the cap's half-angle in degrees, in (0, 180]
 *   toWorld   transform  identity  orientation: the cap is centred on the frame's +z
 *
 *   <emitter type="distantdisk">
 *       <color name="radiance" value="5, 5, 5"/> <float name="thetaA" value="20"/>
 *   </emitter>
 *
 *   <emitter type="distantdisk">
 *       <float name="thetaA" value="180"/>
 *   </emitter>
 */
#include <nori/emitter.h>
#include <nori/proplist.h>
#include <nori/transform.h>
#include <nori/warp.h>

namespace nori {
namespace {

class DistantDisk : public Emitter {
public:
    explicit DistantDisk(const PropertyList &props) {
        m_radiance = props.getColor("radiance", Color3f(1.0f));
        if ((m_radiance < 0.0f).any() || !m_radiance.allFinite())
            throw NoriException("distantdisk: 'radiance' must be finite and not negative");
        m_thetaA = props.getFloat("thetaA", 5.0f);
        if (!(m_thetaA > 0.0f && m_thetaA <= 180.0f))
            throw NoriException("distantdisk: 'thetaA' must be in (0, 180] degrees, got {}",
                                m_thetaA);
        m_cosThetaA = m_thetaA >= 180.0f ? -1.0f : std::cos(degToRad(m_thetaA));
        m_toWorld = props.getTransform("toWorld", Transform());
        m_toLocal = m_toWorld.inverse();
    }

    bool isInfinite() const override { return true; }
    void setSceneBounds(const BoundingBox3f &bounds) override { m_scene.set(bounds); }

    Color3f sample(EmitterQueryRecord &lRec, const Point2f &sample) const override {
        const Vector3f local = Warp::squareToUniformSphereCap(sample, m_cosThetaA);
        lRec.wi = Vector3f(m_toWorld * local).normalized();
        lRec.pdf = Warp::squareToUniformSphereCapPdf(local, m_cosThetaA);
        m_scene.placeBeyond(lRec);
        return lRec.pdf > 0.0f ? Color3f(m_radiance / lRec.pdf) : Color3f(0.0f);
    }

    Color3f sampleEmission(EmissionSample &emission, const Point2f &positionSample,
                           const Point2f &directionSample) const override {
        const Vector3f local = Warp::squareToUniformSphereCap(directionSample, m_cosThetaA);
        const Vector3f toLight = Vector3f(m_toWorld * local).normalized();
        emission.density.direction = Warp::squareToUniformSphereCapPdf(local, m_cosThetaA);
        return m_radiance * (m_scene.photonRayFrom(toLight, positionSample, emission) /
                             emission.density.direction);
    }

    EmissionDensity emissionDensity(const Point3f &, const Normal3f &,
                                    const Vector3f &direction) const override {
        return densityAtInfinity(m_scene, direction);
    }

    Color3f eval(const EmitterQueryRecord &lRec) const override {
        return inCap(lRec.wi) ? m_radiance : Color3f(0.0f);
    }
    float pdf(const EmitterQueryRecord &lRec) const override {
        return inCap(lRec.wi)
                   ? Warp::squareToUniformSphereCapPdf(Vector3f(0.0f, 0.0f, 1.0f), m_cosThetaA)
                   : 0.0f;
    }
    Color3f getPower() const override {
        return m_radiance * (2.0f * kPi * (1.0f - m_cosThetaA) * m_scene.diskArea());
    }

    std::string toString() const override {
        return fmt::format("DistantDisk[radiance={}, thetaA={}, toWorld=\n{}]",
                           m_radiance.toString(), m_thetaA, m_toWorld.toString());
    }

private:
    /// Whether the world direction toward the light lies in the cap.
    bool inCap(const Vector3f &wi) const {
        return Vector3f(m_toLocal * wi).normalized().z() >= m_cosThetaA;
    }

    Color3f m_radiance;
    float m_thetaA, m_cosThetaA;
    Transform m_toWorld, m_toLocal;
    SceneBoundingSphere m_scene;
};

NORI_REGISTER_CLASS(DistantDisk, "distantdisk");

} // namespace
} // namespace nori
