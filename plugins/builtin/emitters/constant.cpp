/*
 * constant — a constant environment: the same radiance from every direction, infinitely
 * far away (Mitsuba's `constant`). Rays that leave the scene see it; directions are
 * sampled uniformly over the sphere (pdf 1/4π); its power is that through the disk of
 * the scene's bounding sphere, 4π L · π r².
 *
 * Parameters:
 *   radiance  color  1  the radiance arriving from every direction
 *
 *   <emitter type="constant"><color name="radiance" value="0.8, 0.9, 1.0"/></emitter>
 */
#include <nori/emitter.h>
#include <nori/proplist.h>
#include <nori/warp.h>

namespace nori {
namespace {

class ConstantEnvironment : public Emitter {
public:
    explicit ConstantEnvironment(const PropertyList &props) {
        m_radiance = props.getColor("radiance", Color3f(1.0f));
        if ((m_radiance < 0.0f).any() || !m_radiance.allFinite())
            throw NoriException("constant: 'radiance' must be finite and not negative");
    }

    bool isInfinite() const override { return true; }
    void setSceneBounds(const BoundingBox3f &bounds) override { m_scene.set(bounds); }

    Color3f sample(EmitterQueryRecord &lRec, const Point2f &sample) const override {
        lRec.wi = Warp::squareToUniformSphere(sample);
        lRec.pdf = Warp::squareToUniformSpherePdf(lRec.wi);
        m_scene.placeBeyond(lRec);
        return m_radiance / lRec.pdf;
    }

    // A direction uniform over the sphere, then a point of the bounding sphere's disk
    // facing it: L·πr²/pdf_ω.
    Color3f sampleEmission(EmissionSample &emission, const Point2f &positionSample,
                           const Point2f &directionSample) const override {
        const Vector3f toLight = Warp::squareToUniformSphere(directionSample);
        emission.density.direction = Warp::squareToUniformSpherePdf(toLight);
        return m_radiance * (m_scene.photonRayFrom(toLight, positionSample, emission) /
                             emission.density.direction);
    }

    EmissionDensity emissionDensity(const Point3f &, const Normal3f &,
                                    const Vector3f &direction) const override {
        return densityAtInfinity(m_scene, direction);
    }

    Color3f eval(const EmitterQueryRecord &) const override { return m_radiance; }
    float pdf(const EmitterQueryRecord &lRec) const override {
        return Warp::squareToUniformSpherePdf(lRec.wi);
    }
    Color3f getPower() const override { return m_radiance * (4.0f * kPi * m_scene.diskArea()); }

    std::string toString() const override {
        return fmt::format("ConstantEnvironment[radiance=({}, {}, {})]", m_radiance.r(),
                           m_radiance.g(), m_radiance.b());
    }

private:
    Color3f m_radiance;
    SceneBoundingSphere m_scene;
};

NORI_REGISTER_CLASS(ConstantEnvironment, "constant");

} // namespace
} // namespace nori
