#include <nori/bsdf.h>
#include <nori/frame.h>
#include <nori/warp.h>

NORI_NAMESPACE_BEGIN

/* The negative control: samples the hemisphere uniformly but reports the cosine
   density, the mistake a student makes when switching warps. The chi-square test
   must reject it. */
class BadPdf : public BSDF {
public:
    BadPdf(const PropertyList &propList) {
        m_albedo = propList.getColor("albedo", Color3f(0.5f));
    }

    Color3f eval(const BSDFQueryRecord &bRec) const {
        if (bRec.measure != ESolidAngle || Frame::cosTheta(bRec.wi) <= 0
            || Frame::cosTheta(bRec.wo) <= 0)
            return Color3f(0.0f);
        return m_albedo * INV_PI;
    }

    float pdf(const BSDFQueryRecord &bRec) const {
        if (bRec.measure != ESolidAngle || Frame::cosTheta(bRec.wi) <= 0
            || Frame::cosTheta(bRec.wo) <= 0)
            return 0.0f;
        return Warp::squareToCosineHemispherePdf(bRec.wo);
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const {
        if (Frame::cosTheta(bRec.wi) <= 0)
            return Color3f(0.0f);
        bRec.measure = ESolidAngle;
        bRec.wo = Warp::squareToUniformHemisphere(sample);
        return m_albedo;
    }

    std::string toString() const {
        return tfm::format("BadPdf[albedo = %s]", m_albedo.toString());
    }
private:
    Color3f m_albedo;
};

NORI_REGISTER_CLASS(BadPdf, "nori2_badpdf");
NORI_NAMESPACE_END
