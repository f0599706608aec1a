/*
 * mirror — an ideal specular reflector: all light leaves in the mirror direction.
 *
 * No parameters.
 *
 *   <bsdf type="mirror"/>
 */
#include <nori/bsdf.h>
#include <nori/frame.h>

namespace nori {
namespace {

class Mirror : public BSDF {
public:
    explicit Mirror(const PropertyList &props) { (void)props; }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &) const override {
        if (Frame::cosTheta(bRec.wi) <= 0.0f)
            return Color3f(0.0f);
        // Reflection about +z in the local frame.
        bRec.wo = Vector3f(-bRec.wi.x(), -bRec.wi.y(), bRec.wi.z());
        bRec.measure = EDiscrete;
        bRec.eta = 1.0f;
        return Color3f(1.0f);
    }

    // A delta distribution has no value or density for any particular pair.
    Color3f eval(const BSDFQueryRecord &) const override { return Color3f(0.0f); }
    float pdf(const BSDFQueryRecord &) const override { return 0.0f; }

    std::string toString() const override { return "Mirror[]"; }
};

NORI_REGISTER_CLASS(Mirror, "mirror");

} // namespace
} // namespace nori
