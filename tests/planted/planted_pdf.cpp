/*
 * planted_pdf — a negative control: cosine-weighted sampling of a Lambertian lobe whose
 * pdf() claims 0.9·cos θ/π, a density that integrates to 0.9. The χ² test must reject it.
 *
 * No parameters.
 *
 *   <bsdf type="planted_pdf"/>
 */
#include <nori/bsdf.h>
#include <nori/frame.h>
#include <nori/warp.h>

namespace nori {

class PlantedPdf : public BSDF {
public:
    explicit PlantedPdf(const PropertyList &) {}

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        if (Frame::cosTheta(bRec.wi) <= 0.0f)
            return Color3f(0.0f);
        bRec.measure = ESolidAngle;
        bRec.wo = Warp::squareToCosineHemisphere(sample);
        return sampleWeight(bRec);
    }
    Color3f eval(const BSDFQueryRecord &bRec) const override {
        const bool above = Frame::cosTheta(bRec.wi) > 0.0f && Frame::cosTheta(bRec.wo) > 0.0f;
        return Color3f(above && bRec.measure == ESolidAngle ? 0.5f * kInvPi : 0.0f);
    }
    float pdf(const BSDFQueryRecord &bRec) const override {
        if (bRec.measure != ESolidAngle || Frame::cosTheta(bRec.wi) <= 0.0f)
            return 0.0f;
        return 0.9f * Warp::squareToCosineHemispherePdf(bRec.wo); // the planted bug
    }
    std::string toString() const override { return "PlantedPdf[]"; }
};

NORI_REGISTER_CLASS(PlantedPdf, "planted_pdf");

} // namespace nori
