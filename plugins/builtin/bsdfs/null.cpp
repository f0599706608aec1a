/*
 * null — no surface at all: light passes straight through, unchanged. It marks the
 * boundary of a participating medium with the same index of refraction on both sides
 * (PBR 4th ed. §11.4; Mitsuba's "null"). A shape that carries a medium and no BSDF gets
 * this one. volpath crosses it without counting a bounce and traces shadow rays through
 * it; the other integrators see a perfectly clear specular transmission.
 *
 * No parameters.
 *
 *   <bsdf type="null"/>
 */
#include <nori/bsdf.h>

namespace nori {
namespace {

class NullBSDF : public BSDF {
public:
    explicit NullBSDF(const PropertyList &props) { (void)props; }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &) const override {
        bRec.wo = -bRec.wi;
        bRec.measure = EDiscrete;
        bRec.eta = 1.0f;
        return Color3f(1.0f);
    }

    // A delta distribution has no value or density for any particular pair.
    Color3f eval(const BSDFQueryRecord &) const override { return Color3f(0.0f); }
    float pdf(const BSDFQueryRecord &) const override { return 0.0f; }
    bool isNull() const override { return true; }

    std::string toString() const override { return "NullBSDF[]"; }
};

NORI_REGISTER_CLASS(NullBSDF, "null");

} // namespace
} // namespace nori
