// A microfacet BSDF as a Nori 2 course's assignment has students write it: a Beckmann
// lobe (with Nori's rational approximation of Smith's shadowing) over a diffuse base,
// under the name the handout gives it. Test data of tests/CMakeLists.txt ("course"): it
// replaces our `microfacet`. Compiled with -DCOURSE_PLANTED_BUG it forgets the Jacobian
// 1/(4 wh.wo) of the reflection in pdf(), the bug the automatic test must catch.
#include <nori/bsdf.h>
#include <nori/frame.h>
#include <nori/warp.h>

NORI_NAMESPACE_BEGIN

class Microfacet : public BSDF {
public:
    Microfacet(const PropertyList &propList) {
        m_alpha = propList.getFloat("alpha", 0.1f);
        m_intIOR = propList.getFloat("intIOR", 1.5046f);
        m_extIOR = propList.getFloat("extIOR", 1.000277f);
        m_kd = propList.getColor("kd", Color3f(0.5f));
        m_ks = 1 - m_kd.maxCoeff();
    }

    /// Smith's shadowing of one direction, Nori's rational approximation
    float G1(const Vector3f &wv, const Vector3f &wh) const {
        if (wv.dot(wh) / Frame::cosTheta(wv) <= 0)
            return 0.0f;
        float b = 1.0f / (m_alpha * Frame::tanTheta(wv));
        if (b >= 1.6f)
            return 1.0f;
        return (3.535f * b + 2.181f * b * b) / (1.0f + 2.276f * b + 2.577f * b * b);
    }

    Color3f eval(const BSDFQueryRecord &bRec) const {
        if (bRec.measure != ESolidAngle || Frame::cosTheta(bRec.wi) <= 0 ||
            Frame::cosTheta(bRec.wo) <= 0)
            return Color3f(0.0f);
        Vector3f wh = (bRec.wi + bRec.wo).normalized();
        float D = Warp::squareToBeckmannPdf(wh, m_alpha);
        float F = fresnel(wh.dot(bRec.wi), m_extIOR, m_intIOR);
        float G = G1(bRec.wi, wh) * G1(bRec.wo, wh);
        return m_kd * INV_PI + m_ks * D * F * G /
                                   (4.0f * Frame::cosTheta(bRec.wi) * Frame::cosTheta(bRec.wo) *
                                    Frame::cosTheta(wh));
    }

    float pdf(const BSDFQueryRecord &bRec) const {
        if (bRec.measure != ESolidAngle || Frame::cosTheta(bRec.wi) <= 0 ||
            Frame::cosTheta(bRec.wo) <= 0)
            return 0.0f;
        Vector3f wh = (bRec.wi + bRec.wo).normalized();
#ifdef COURSE_PLANTED_BUG
        float jacobian = 1.0f;
#else
        float jacobian = 1.0f / (4.0f * wh.dot(bRec.wo));
#endif
        return m_ks * Warp::squareToBeckmannPdf(wh, m_alpha) * jacobian +
               (1 - m_ks) * Frame::cosTheta(bRec.wo) * INV_PI;
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &_sample) const {
        if (Frame::cosTheta(bRec.wi) <= 0)
            return Color3f(0.0f);
        bRec.measure = ESolidAngle;
        bRec.eta = 1.0f;
        Point2f sample(_sample);
        if (sample.x() < m_ks) {
            sample.x() /= m_ks;
            Vector3f wh = Warp::squareToBeckmann(sample, m_alpha);
            bRec.wo = 2.0f * wh.dot(bRec.wi) * wh - bRec.wi;
        } else {
            sample.x() = (sample.x() - m_ks) / (1 - m_ks);
            bRec.wo = Warp::squareToCosineHemisphere(sample);
        }
        if (Frame::cosTheta(bRec.wo) <= 0)
            return Color3f(0.0f);
        return eval(bRec) * Frame::cosTheta(bRec.wo) / pdf(bRec);
    }

    bool isDiffuse() const {
        return true;
    }

    std::string toString() const {
        return tfm::format("Microfacet[\n"
                           "  alpha = %f,\n"
                           "  intIOR = %f,\n"
                           "  extIOR = %f,\n"
                           "  kd = %s,\n"
                           "  ks = %f\n"
                           "]",
                           m_alpha, m_intIOR, m_extIOR, m_kd.toString(), m_ks);
    }

private:
    float m_alpha;
    float m_intIOR, m_extIOR;
    float m_ks;
    Color3f m_kd;
};

NORI_REGISTER_CLASS(Microfacet, "microfacet");
NORI_NAMESPACE_END
