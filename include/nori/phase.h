// Phase functions of participating media. As with BSDFs, wi and wo both point away from
// the scattering point, so forward scattering means wo ≈ −wi.
#pragma once

#include <nori/bsdf.h>

namespace nori {

struct PhaseFunctionQueryRecord {
    Vector3f wi;
    Vector3f wo;
    EMeasure measure = EUnknownMeasure;

    explicit PhaseFunctionQueryRecord(const Vector3f &wi) : wi(wi) {}
    PhaseFunctionQueryRecord(const Vector3f &wi, const Vector3f &wo, EMeasure measure)
        : wi(wi), wo(wo), measure(measure) {}
};

class PhaseFunction : public NoriObject {
public:
    static constexpr EClassType kClassType = EPhaseFunction;

    /// Samples wo; returns eval/pdf (zero on failure).
    virtual Color3f sample(PhaseFunctionQueryRecord &pRec, const Point2f &sample) const = 0;
    virtual Color3f eval(const PhaseFunctionQueryRecord &pRec) const = 0;
    virtual float pdf(const PhaseFunctionQueryRecord &pRec) const = 0;

    EClassType getClassType() const override { return kClassType; }
};

} // namespace nori
