/*
 * dielectric — a smooth interface between two dielectrics (glass, water): specular
 * reflection with probability F and refraction otherwise (PBR 4th ed. §9.5). Refracted
 * radiance is scaled by (η_i/η_t)², as radiance transport requires.
 *
 * Parameters:
 *   intIOR  float  1.5046    index of refraction inside (BK7 glass)
 *   extIOR  float  1.000277  index of refraction outside (air)
 *
 *   <bsdf type="dielectric"><float name="intIOR" value="1.33"/></bsdf>
 */
#include <nori/bsdf.h>
#include <nori/frame.h>
#include <nori/fresnel.h>

namespace nori {
namespace {

class Dielectric : public BSDF {
public:
    explicit Dielectric(const PropertyList &props) {
        m_intIOR = props.getFloat("intIOR", 1.5046f);
        m_extIOR = props.getFloat("extIOR", 1.000277f);
        if (!(m_intIOR > 0.0f && m_extIOR > 0.0f))
            throw NoriException("dielectric: 'intIOR' and 'extIOR' must be positive, got {} and {}",
                                m_intIOR, m_extIOR);
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        const float cosThetaI = Frame::cosTheta(bRec.wi);
        const float fresnel = fresnelDielectric(cosThetaI, m_extIOR, m_intIOR);
        bRec.measure = EDiscrete;
        if (sample.x() < fresnel) {
            // Reflection, chosen with probability F: weight F/F = 1.
            bRec.wo = Vector3f(-bRec.wi.x(), -bRec.wi.y(), bRec.wi.z());
            bRec.eta = 1.0f;
            return Color3f(1.0f);
        }
        // Refraction, chosen with probability 1 − F: weight (1 − F)/(1 − F) times the
        // radiance scaling. eta is η_t/η_i for the side wi is on.
        const bool outside = cosThetaI > 0.0f;
        const float eta = outside ? m_intIOR / m_extIOR : m_extIOR / m_intIOR;
        const Vector3f normal(0.0f, 0.0f, outside ? 1.0f : -1.0f);
        if (!refract(bRec.wi, normal, eta, bRec.wo))
            return Color3f(0.0f); // unreachable: F = 1 under total internal reflection
        bRec.eta = eta;
        return Color3f(1.0f / (eta * eta));
    }

    Color3f eval(const BSDFQueryRecord &) const override { return Color3f(0.0f); }
    float pdf(const BSDFQueryRecord &) const override { return 0.0f; }

    std::string toString() const override {
        return fmt::format("Dielectric[intIOR={}, extIOR={}]", m_intIOR, m_extIOR);
    }

private:
    float m_intIOR, m_extIOR;
};

NORI_REGISTER_CLASS(Dielectric, "dielectric");

} // namespace
} // namespace nori
