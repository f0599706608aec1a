/*
 * thindielectric — a thin pane of glass, a window (Mitsuba 0.6 documentation,
 * "thindielectric"; PBR 4th ed. §9.5.3): two parallel smooth interfaces so close that
 * light leaves where it entered, undeflected. Summing the light reflected inside the pane
 * again and again, R = F + T²F/(1 − F²) (a geometric series; F the Fresnel reflectance of
 * one interface) is reflected specularly and 1 − R passes straight through, from either
 * side. A closed shape of it holds no medium: light crossing it does not change medium.
 *
 * Parameters:
 *   intIOR                 float          1.5046    index of refraction of the pane, or a
 *                                                   name ("bk7", "water", ...)
 *   extIOR                 float          1.000277  index of refraction outside, or a name
 *   specularReflectance    color/texture  1         scales the reflection (Mitsuba's)
 *   specularTransmittance  color/texture  1         scales the transmission (Mitsuba's)
 *
 *   <bsdf type="thindielectric"/>
 *
 *   <bsdf type="thindielectric"><float name="intIOR" value="1.8"/>
 *       <color name="specularTransmittance" value="0.9, 0.95, 0.9"/></bsdf>
 */
#include <nori/bsdf.h>
#include <nori/bsdfparams.h>
#include <nori/frame.h>
#include <nori/fresnel.h>

namespace nori {
namespace {

class ThinDielectric : public BSDF {
public:
    explicit ThinDielectric(const PropertyList &props) {
        m_intIOR = readIOR(props, "intIOR", 1.5046f, "thindielectric");
        m_extIOR = readIOR(props, "extIOR", 1.000277f, "thindielectric");
        m_reflectance = m_textures.color(props, "specularReflectance", Color3f(1.0f));
        m_transmittance = m_textures.color(props, "specularTransmittance", Color3f(1.0f));
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        const float reflected = reflectance(Frame::cosTheta(bRec.wi));
        bRec.measure = EDiscrete;
        bRec.eta = 1.0f;
        if (sample.x() < reflected) {
            // Chosen with probability R: weight R/R, times Mitsuba's scale.
            bRec.wo = Vector3f(-bRec.wi.x(), -bRec.wi.y(), bRec.wi.z());
            return m_reflectance->eval(bRec).max(0.0f);
        }
        bRec.wo = -bRec.wi;
        return m_transmittance->eval(bRec).max(0.0f);
    }

    int discreteLobes(const BSDFQueryRecord &bRec, DiscreteLobe *lobes) const override {
        const float reflected = reflectance(Frame::cosTheta(bRec.wi));
        lobes[0] = {Vector3f(-bRec.wi.x(), -bRec.wi.y(), bRec.wi.z()), 1.0f, reflected,
                    m_reflectance->eval(bRec).max(0.0f) * reflected};
        if (reflected >= 1.0f)
            return 1;
        lobes[1] = {-bRec.wi, 1.0f, 1.0f - reflected,
                    m_transmittance->eval(bRec).max(0.0f) * (1.0f - reflected)};
        return 2;
    }

    Color3f eval(const BSDFQueryRecord &) const override { return Color3f(0.0f); }
    float pdf(const BSDFQueryRecord &) const override { return 0.0f; }

    std::string toString() const override {
        return fmt::format("ThinDielectric[intIOR={}, extIOR={}]", m_intIOR, m_extIOR);
    }

private:
    /// R = F + (1 − F)² F/(1 − F²) = 2F/(1 + F), the pane's reflectance with every
    /// internal bounce (PBR 4th ed. eq. 9.28 and the series after it).
    float reflectance(float cosThetaI) const {
        const float fresnel = fresnelDielectric(std::abs(cosThetaI), m_extIOR, m_intIOR);
        return fresnel < 1.0f ? 2.0f * fresnel / (1.0f + fresnel) : 1.0f;
    }

    float m_intIOR, m_extIOR;
    std::shared_ptr<const Texture> m_reflectance, m_transmittance;
};

NORI_REGISTER_CLASS(ThinDielectric, "thindielectric");

} // namespace
} // namespace nori
