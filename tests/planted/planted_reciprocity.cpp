/*
 * planted_reciprocity — a negative control: a glossy lobe about the mirror direction whose
 * value is weighted by cos θi (which depends on wi only), so f(wi, wo) ≠ f(wo, wi). Its
 * sample() and pdf() agree and its weight is eval·cos/pdf; only reciprocity fails.
 *
 * No parameters.
 *
 *   <bsdf type="planted_reciprocity"/>
 */
#include <nori/bsdf.h>
#include <nori/frame.h>
#include <nori/warp.h>

namespace nori {

class PlantedReciprocity : public BSDF {
public:
    explicit PlantedReciprocity(const PropertyList &) {}

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        if (Frame::cosTheta(bRec.wi) <= 0.0f)
            return Color3f(0.0f);
        bRec.measure = ESolidAngle;
        bRec.wo = Warp::squareToCosineHemisphere(sample);
        return sampleWeight(bRec);
    }
    Color3f eval(const BSDFQueryRecord &bRec) const override {
        if (bRec.measure != ESolidAngle || Frame::cosTheta(bRec.wi) <= 0.0f ||
            Frame::cosTheta(bRec.wo) <= 0.0f)
            return Color3f(0.0f);
        return Color3f(0.5f * kInvPi * Frame::cosTheta(bRec.wi)); // the planted bug
    }
    float pdf(const BSDFQueryRecord &bRec) const override {
        if (bRec.measure != ESolidAngle || Frame::cosTheta(bRec.wi) <= 0.0f)
            return 0.0f;
        return Warp::squareToCosineHemispherePdf(bRec.wo);
    }
    std::string toString() const override { return "PlantedReciprocity[]"; }
};

NORI_REGISTER_CLASS(PlantedReciprocity, "planted_reciprocity");

} // namespace nori
