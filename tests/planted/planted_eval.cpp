/*
 * planted_eval — a negative control: sample() and pdf() agree (cosine sampling), but
 * eval() returns albedo/π only for half the directions, so the value integrators use
 * differs from the weight sample() returns. The χ² test cannot see it; the weight check
 * must.
 *
 * No parameters.
 *
 *   <bsdf type="planted_eval"/>
 */
#include <nori/bsdf.h>
#include <nori/frame.h>
#include <nori/warp.h>

namespace nori {

class PlantedEval : public BSDF {
public:
    explicit PlantedEval(const PropertyList &) {}

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        if (Frame::cosTheta(bRec.wi) <= 0.0f)
            return Color3f(0.0f);
        bRec.measure = ESolidAngle;
        bRec.wo = Warp::squareToCosineHemisphere(sample);
        return Color3f(0.5f);
    }
    Color3f eval(const BSDFQueryRecord &bRec) const override {
        if (bRec.measure != ESolidAngle || Frame::cosTheta(bRec.wi) <= 0.0f ||
            Frame::cosTheta(bRec.wo) <= 0.0f)
            return Color3f(0.0f);
        return Color3f(bRec.wo.x() > 0.0f ? 0.5f * kInvPi : 0.25f * kInvPi); // the planted bug
    }
    float pdf(const BSDFQueryRecord &bRec) const override {
        if (bRec.measure != ESolidAngle || Frame::cosTheta(bRec.wi) <= 0.0f)
            return 0.0f;
        return Warp::squareToCosineHemispherePdf(bRec.wo);
    }
    std::string toString() const override { return "PlantedEval[]"; }
};

NORI_REGISTER_CLASS(PlantedEval, "planted_eval");

} // namespace nori
