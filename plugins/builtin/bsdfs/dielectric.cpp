/*
 * dielectric — a smooth interface between two dielectrics (glass, water): specular
 * reflection with probability F and refraction otherwise (PBR 4th ed. §9.5). Refracted
 * radiance is scaled by (η_i/η_t)², as radiance transport requires.
 *
 * Parameters:
 *   intIOR  float  1.5046    index of refraction inside (BK7 glass), or a name from
 *                            Mitsuba's table ("water", "diamond", "bk7", ...)
 *   extIOR  float  1.000277  index of refraction outside (air), or a name
 *
 *   <bsdf type="dielectric"><float name="intIOR" value="1.33"/></bsdf>
 */
#include <nori/bsdf.h>
#include <nori/bsdfparams.h>
#include <nori/frame.h>
#include <nori/fresnel.h>

namespace nori {
namespace {

class Dielectric : public BSDF {
public:
    explicit Dielectric(const PropertyList &props) {
        m_intIOR = readIOR(props, "intIOR", 1.5046f, "dielectric");
        m_extIOR = readIOR(props, "extIOR", 1.000277f, "dielectric");
        if (!(m_intIOR > 0.0f && m_extIOR > 0.0f))
            throw NoriException("dielectric: 'intIOR' and 'extIOR' must be positive, got {} and {}",
                                m_intIOR, m_extIOR);
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        const float fresnel = fresnelDielectric(Frame::cosTheta(bRec.wi), m_extIOR, m_intIOR);
        bRec.measure = EDiscrete;
        if (sample.x() < fresnel) {
            // Reflection, chosen with probability F: weight F/F = 1.
            bRec.wo = reflection(bRec.wi);
            bRec.eta = 1.0f;
            return Color3f(1.0f);
        }
        // Refraction, chosen with probability 1 − F: weight (1 − F)/(1 − F) times the
        // radiance scaling.
        if (!refraction(bRec.wi, bRec.wo, bRec.eta))
            return Color3f(0.0f); // unreachable: F = 1 under total internal reflection
        return Color3f(1.0f / (bRec.eta * bRec.eta));
    }

    int discreteLobes(const BSDFQueryRecord &bRec, DiscreteLobe *lobes) const override {
        const float fresnel = fresnelDielectric(Frame::cosTheta(bRec.wi), m_extIOR, m_intIOR);
        lobes[0] = {reflection(bRec.wi), 1.0f, fresnel, Color3f(fresnel)};
        DiscreteLobe &refracted = lobes[1];
        if (fresnel >= 1.0f || !refraction(bRec.wi, refracted.wo, refracted.eta))
            return 1; // total internal reflection
        refracted.probability = 1.0f - fresnel;
        refracted.weight = Color3f((1.0f - fresnel) / (refracted.eta * refracted.eta));
        return 2;
    }

    Color3f eval(const BSDFQueryRecord &) const override { return Color3f(0.0f); }
    float pdf(const BSDFQueryRecord &) const override { return 0.0f; }

    std::string toString() const override {
        return fmt::format("Dielectric[intIOR={}, extIOR={}]", m_intIOR, m_extIOR);
    }

private:
    static Vector3f reflection(const Vector3f &wi) { return {-wi.x(), -wi.y(), wi.z()}; }

    /// The refracted direction of wi and eta = η_t/η_i for the side wi is on; false under
    /// total internal reflection.
    bool refraction(const Vector3f &wi, Vector3f &wo, float &eta) const {
        const bool outside = Frame::cosTheta(wi) > 0.0f;
        eta = outside ? m_intIOR / m_extIOR : m_extIOR / m_intIOR;
        return refract(wi, Vector3f(0.0f, 0.0f, outside ? 1.0f : -1.0f), eta, wo);
    }

    float m_intIOR, m_extIOR;
};

NORI_REGISTER_CLASS(Dielectric, "dielectric");

} // namespace
} // namespace nori
