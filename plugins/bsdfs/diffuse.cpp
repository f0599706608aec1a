/*
 * diffuse — an ideal Lambertian reflector (PBR 4th ed. §9.2).
 *
 * Parameters:
 *   albedo  color  0.5  fraction of light reflected, per channel, in [0, 1]
 *
 *   <bsdf type="diffuse">
 *       <color name="albedo" value="0.7, 0.2, 0.2"/>
 *   </bsdf>
 */
#include <nori/bsdf.h>
#include <nori/frame.h>
#include <nori/warp.h>

namespace nori {

class Diffuse : public BSDF {
public:
    explicit Diffuse(const PropertyList &props) {
        m_albedo = props.getColor("albedo", Color3f(0.5f));
        if ((m_albedo < 0.0f).any() || (m_albedo > 1.0f).any())
            throw NoriException("diffuse: 'albedo' must lie in [0, 1], got ({}, {}, {})",
                                m_albedo.r(), m_albedo.g(), m_albedo.b());
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        if (Frame::cosTheta(bRec.wi) <= 0.0f)
            return Color3f(0.0f);
        bRec.measure = ESolidAngle;
        bRec.wo = Warp::squareToCosineHemisphere(sample);
        bRec.eta = 1.0f;
        // eval·cos/pdf = (albedo/π)·cos / (cos/π) = albedo.
        return m_albedo;
    }

    Color3f eval(const BSDFQueryRecord &bRec) const override {
        if (bRec.measure != ESolidAngle || Frame::cosTheta(bRec.wi) <= 0.0f ||
            Frame::cosTheta(bRec.wo) <= 0.0f)
            return Color3f(0.0f);
        return m_albedo * kInvPi;
    }

    float pdf(const BSDFQueryRecord &bRec) const override {
        if (bRec.measure != ESolidAngle || Frame::cosTheta(bRec.wi) <= 0.0f ||
            Frame::cosTheta(bRec.wo) <= 0.0f)
            return 0.0f;
        return Warp::squareToCosineHemispherePdf(bRec.wo);
    }

    bool isDiffuse() const override { return true; }

    std::string toString() const override {
        return fmt::format("Diffuse[albedo=({}, {}, {})]", m_albedo.r(), m_albedo.g(),
                           m_albedo.b());
    }

private:
    Color3f m_albedo;
};

NORI_REGISTER_CLASS(Diffuse, "diffuse");

} // namespace nori
