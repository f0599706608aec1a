#include <nori/bsdf.h>
#include <nori/frame.h>
#include <nori/warp.h>

NORI_NAMESPACE_BEGIN

/// Modified Phong BSDF (Lafortune and Willems 1994), in the style of a Nori 2 course file
class Phong : public BSDF {
public:
    Phong(const PropertyList &propList) {
        m_kd = propList.getColor("kd", Color3f(0.5f));
        m_ks = propList.getColor("ks", Color3f(0.2f));
        m_exponent = propList.getFloat("exponent", 20.0f);
        if (m_exponent < 0)
            throw NoriException("Phong: the exponent must be positive (got %f)!", m_exponent);
        float kd = m_kd.getLuminance(), ks = m_ks.getLuminance();
        m_diffuseProb = kd / (kd + ks);
    }

    /// cosine of the angle between wo and the mirror direction of wi
    float cosAlpha(const BSDFQueryRecord &bRec) const {
        Vector3f reflected(-bRec.wi.x(), -bRec.wi.y(), bRec.wi.z());
        return std::max(0.0f, reflected.dot(bRec.wo));
    }

    Color3f eval(const BSDFQueryRecord &bRec) const {
        if (bRec.measure != ESolidAngle || Frame::cosTheta(bRec.wi) <= 0
            || Frame::cosTheta(bRec.wo) <= 0)
            return 0.0f;
        float lobe = (m_exponent + 2) * INV_TWOPI * std::pow(cosAlpha(bRec), m_exponent);
        return m_kd * INV_PI + m_ks * lobe;
    }

    float pdf(const BSDFQueryRecord &bRec) const {
        if (bRec.measure != ESolidAngle || Frame::cosTheta(bRec.wi) <= 0
            || Frame::cosTheta(bRec.wo) <= 0)
            return 0.0f;
        float specular = (m_exponent + 1) * INV_TWOPI * std::pow(cosAlpha(bRec), m_exponent);
        return m_diffuseProb * Warp::squareToCosineHemispherePdf(bRec.wo)
            + (1 - m_diffuseProb) * specular;
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &_sample) const {
        if (Frame::cosTheta(bRec.wi) <= 0)
            return Color3f(0.0f);
        Point2f sample(_sample);
        bRec.measure = ESolidAngle;
        bRec.eta = 1.0f;
        if (sample.x() < m_diffuseProb) {
            sample.x() /= m_diffuseProb;
            bRec.wo = Warp::squareToCosineHemisphere(sample);
        } else {
            sample.x() = (sample.x() - m_diffuseProb) / (1 - m_diffuseProb);
            float theta = std::acos(std::pow(sample.x(), 1 / (m_exponent + 1)));
            float phi = 2 * M_PI * sample.y();
            Frame lobe(Vector3f(-bRec.wi.x(), -bRec.wi.y(), bRec.wi.z()));
            bRec.wo = lobe.toWorld(sphericalDirection(theta, phi));
        }
        if (Frame::cosTheta(bRec.wo) <= 0)
            return Color3f(0.0f);
        float density = pdf(bRec);
        if (density <= 0)
            return Color3f(0.0f);
        return eval(bRec) * Frame::cosTheta(bRec.wo) / density;
    }

    std::string toString() const {
        return tfm::format(
            "Phong[\n"
            "  kd = %s,\n"
            "  ks = %s,\n"
            "  exponent = %.3f\n"
            "]", m_kd.toString(), m_ks.toString(), m_exponent);
    }

    EClassType getClassType() const { return EBSDF; }
private:
    Color3f m_kd, m_ks;
    float m_exponent;
    float m_diffuseProb;
};

NORI_REGISTER_CLASS(Phong, "nori2_phong");
NORI_NAMESPACE_END
