/*
 * hg — the Henyey–Greenstein phase function (PBR 4th ed. §11.3.1): one parameter from
 * back scattering (g < 0) through isotropic (g = 0) to forward scattering (g > 0).
 * Sampled exactly, so sample() returns a weight of 1.
 *
 * Parameters:
 *   g  float  0  mean cosine of the scattering angle, in (−1, 1)
 *
 *   <phase type="hg"><float name="g" value="0.7"/></phase>
 *
 *   <phase type="henyey"><float name="g" value="-0.3"/></phase>
 *
 *   <phase type="henyeyGreenstein"><float name="g" value="0.2"/></phase>
 *
 * Also registered as: henyey, henyeyGreenstein.
 */
#include <nori/frame.h>
#include <nori/phase.h>
#include <nori/warp.h>

namespace nori {
namespace {

class HenyeyGreenstein : public PhaseFunction {
public:
    explicit HenyeyGreenstein(const PropertyList &props) {
        m_g = props.getFloat("g", 0.0f);
        if (!(m_g > -1.0f && m_g < 1.0f))
            throw NoriException("hg: 'g' must lie in (-1, 1), got {}", m_g);
    }

    Color3f sample(PhaseFunctionQueryRecord &pRec, const Point2f &sample) const override {
        // Directions about the propagation direction −wi.
        pRec.wo = Frame(Vector3f(-pRec.wi)).toWorld(Warp::squareToHenyeyGreenstein(sample, m_g));
        pRec.measure = ESolidAngle;
        return Color3f(1.0f);
    }

    Color3f eval(const PhaseFunctionQueryRecord &pRec) const override { return Color3f(pdf(pRec)); }

    float pdf(const PhaseFunctionQueryRecord &pRec) const override {
        if (pRec.measure != ESolidAngle)
            return 0.0f;
        return Warp::squareToHenyeyGreensteinPdf(Frame(Vector3f(-pRec.wi)).toLocal(pRec.wo), m_g);
    }

    std::string toString() const override { return fmt::format("HenyeyGreenstein[g={}]", m_g); }

private:
    float m_g;
};

NORI_REGISTER_CLASS(HenyeyGreenstein, "hg");
NORI_REGISTER_ALIAS(HenyeyGreenstein, "henyey", henyey);
NORI_REGISTER_ALIAS(HenyeyGreenstein, "henyeyGreenstein", henyeyGreenstein);

} // namespace
} // namespace nori
