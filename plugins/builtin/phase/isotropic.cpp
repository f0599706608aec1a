/*
 * isotropic — scattering equally into every direction, p = 1/(4π) (PBR 4th ed. §11.3).
 * Sampled exactly, so sample() returns a weight of 1.
 *
 * No parameters.
 *
 *   <phase type="isotropic"/>
 */
#include <nori/phase.h>
#include <nori/warp.h>

namespace nori {
namespace {

class IsotropicPhase : public PhaseFunction {
public:
    explicit IsotropicPhase(const PropertyList &) {}

    Color3f sample(PhaseFunctionQueryRecord &pRec, const Point2f &sample) const override {
        pRec.wo = Warp::squareToUniformSphere(sample);
        pRec.measure = ESolidAngle;
        return Color3f(1.0f);
    }

    Color3f eval(const PhaseFunctionQueryRecord &pRec) const override { return Color3f(pdf(pRec)); }

    float pdf(const PhaseFunctionQueryRecord &pRec) const override {
        return pRec.measure == ESolidAngle ? kInvFourPi : 0.0f;
    }

    std::string toString() const override { return "IsotropicPhase[]"; }
};

NORI_REGISTER_CLASS(IsotropicPhase, "isotropic");

} // namespace
} // namespace nori
