/*
 * roughdielectric — a rough interface between two dielectrics (frosted glass):
 * microfacet reflection and refraction of Walter et al. 2007 (eqs. 20–21), Beckmann or
 * GGX, usable from either side. wi is the direction toward the viewer, so light arrives
 * along wo; refracted radiance is scaled by (η_wi/η_wo)² as radiance transport requires.
 *
 * Parameters:
 *   distribution  string  "ggx"     "beckmann" or "ggx"
 *   alpha         float/texture  0.1       roughness (> 0)
 *   alphaU, alphaV  float/texture  —       anisotropic roughness along the shading frame's
 *                                   tangent and bitangent, instead of alpha
 *   remapRoughness  boolean  false    the roughness values are pbrt-v4's r, α = √r
 *   intIOR        float   1.5046    index of refraction inside, or a name ("water",
 *                                   "bk7", ...; Mitsuba's table)
 *   extIOR        float   1.000277  index of refraction outside, or a name
 *
 *   <bsdf type="roughdielectric"><float name="alpha" value="0.2"/></bsdf>
 */
#include <nori/bsdf.h>
#include <nori/bsdfparams.h>
#include <nori/frame.h>
#include <nori/fresnel.h>
#include <nori/microfacet.h>

namespace nori {
namespace {

class RoughDielectric : public BSDF {
public:
    explicit RoughDielectric(const PropertyList &props)
        : m_roughness(MicrofacetDistribution::parseType(props.getString("distribution", "ggx")),
                      props, m_textures, "roughdielectric") {
        m_intIOR = readIOR(props, "intIOR", 1.5046f, "roughdielectric");
        m_extIOR = readIOR(props, "extIOR", 1.000277f, "roughdielectric");
        if (!(m_intIOR > 0.0f && m_extIOR > 0.0f) || m_intIOR == m_extIOR)
            throw NoriException("roughdielectric: need positive, different 'intIOR' and 'extIOR'");
    }

    Color3f eval(const BSDFQueryRecord &bRec) const override {
        const MicrofacetDistribution distribution = m_roughness.at(bRec);
        Geometry g;
        if (bRec.measure != ESolidAngle || !geometry(bRec.wi, bRec.wo, g))
            return Color3f(0.0f);
        const float D = distribution.D(g.h), G = distribution.G(bRec.wi, bRec.wo, g.h);
        const float cosI = std::abs(Frame::cosTheta(bRec.wi)),
                    cosO = std::abs(Frame::cosTheta(bRec.wo));
        if (g.reflection)
            return Color3f(fresnelDielectric(bRec.wi.dot(g.h), m_extIOR, m_intIOR) * D * G /
                           (4.0f * cosI * cosO));
        // F is the same from both sides of a refraction. From inside, near total internal
        // reflection, cos θt = √(1 − sin²θt) loses its digits in single precision, so F is
        // computed from the outside, where it is well conditioned (and f stays reciprocal).
        const Vector3f &outside = Frame::cosTheta(bRec.wi) > 0.0f ? bRec.wi : bRec.wo;
        const float F = fresnelDielectric(outside.dot(g.h), m_extIOR, m_intIOR);
        // Walter eq. 21 with light arriving along wo: the viewer's side is "o" there.
        const float iDotH = bRec.wi.dot(g.h), oDotH = bRec.wo.dot(g.h);
        const float denominator = g.etaO * oDotH + g.etaI * iDotH;
        const float value = std::abs(iDotH * oDotH) * g.etaI * g.etaI * (1.0f - F) * D * G /
                            (cosI * cosO * denominator * denominator);
        return Color3f(value);
    }

    float pdf(const BSDFQueryRecord &bRec) const override {
        const MicrofacetDistribution distribution = m_roughness.at(bRec);
        Geometry g;
        if (bRec.measure != ESolidAngle || !geometry(bRec.wi, bRec.wo, g))
            return 0.0f;
        const float reflectProbability = reflectionProbability(Frame::cosTheta(bRec.wi));
        const float normalPdf = distribution.pdfNormal(g.h);
        if (g.reflection)
            return reflectProbability * normalPdf / (4.0f * std::abs(bRec.wo.dot(g.h)));
        // Jacobian of refraction from wi (Walter eq. 17): η_o²|wo·h| / (η_i (wi·h) + η_o (wo·h))².
        const float denominator = g.etaI * bRec.wi.dot(g.h) + g.etaO * bRec.wo.dot(g.h);
        return (1.0f - reflectProbability) * normalPdf * g.etaO * g.etaO *
               std::abs(bRec.wo.dot(g.h)) / (denominator * denominator);
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        const MicrofacetDistribution distribution = m_roughness.at(bRec);
        const float cosI = Frame::cosTheta(bRec.wi);
        if (cosI == 0.0f)
            return Color3f(0.0f);
        // Choose the lobe first, with a probability that depends on wi only (F(m) is not
        // known before m is drawn), then reuse the rescaled sample for the normal.
        const float reflectProbability = reflectionProbability(cosI);
        const bool reflection = sample.x() < reflectProbability;
        const Point2f reused(reflection
                                 ? sample.x() / reflectProbability
                                 : (sample.x() - reflectProbability) / (1.0f - reflectProbability),
                             sample.y());
        // A microfacet normal on wi's side of the macro-surface.
        Vector3f m = distribution.sampleNormal(reused);
        if (cosI < 0.0f)
            m = -m;
        // A microfacet facing away from wi is shadowed (G1 = 0): no sample.
        if (bRec.wi.dot(m) <= 0.0f)
            return Color3f(0.0f);
        bRec.measure = ESolidAngle;
        if (reflection) {
            bRec.wo = reflect(bRec.wi, m);
            bRec.eta = 1.0f;
        } else {
            const float eta = cosI > 0.0f ? m_intIOR / m_extIOR : m_extIOR / m_intIOR;
            if (!refract(bRec.wi, m, eta, bRec.wo))
                return Color3f(0.0f); // total internal reflection at this microfacet
            bRec.eta = eta;
        }
        // A rough normal can send the direction to the wrong side of the macro-surface;
        // pdf() would read such a pair as the other lobe, so it is no sample.
        const bool sameSide = Frame::cosTheta(bRec.wo) * cosI > 0.0f;
        if (sameSide != reflection)
            return Color3f(0.0f);
        return sampleWeight(bRec);
    }

    /// Not a delta distribution, so integrators should sample lights here too.
    bool isDiffuse() const override { return true; }

    std::string toString() const override {
        return fmt::format("RoughDielectric[distribution={}, {}, intIOR={}, extIOR={}]",
                           m_roughness.type() == MicrofacetDistribution::Type::GGX ? "ggx"
                                                                                   : "beckmann",
                           m_roughness.toString(), m_intIOR, m_extIOR);
    }

private:
    /// Probability of sampling the reflection lobe: the Fresnel reflectance at the
    /// macro-normal, kept within [0.1, 0.9] so that neither lobe is ever left unsampled
    /// (its density must be positive wherever its value is).
    float reflectionProbability(float cosThetaI) const {
        return std::clamp(fresnelDielectric(cosThetaI, m_extIOR, m_intIOR), 0.1f, 0.9f);
    }

    /// The half vector of a pair and the indices on each side.
    struct Geometry {
        Vector3f h;       ///< (generalised) half vector, on the +z side
        bool reflection;  ///< wi and wo on the same side
        float etaI, etaO; ///< indices of refraction on wi's and wo's side
    };

    bool geometry(const Vector3f &wi, const Vector3f &wo, Geometry &g) const {
        const float cosI = Frame::cosTheta(wi), cosO = Frame::cosTheta(wo);
        if (cosI == 0.0f || cosO == 0.0f)
            return false;
        g.reflection = cosI * cosO > 0.0f;
        g.etaI = cosI > 0.0f ? m_extIOR : m_intIOR;
        g.etaO = cosO > 0.0f ? m_extIOR : m_intIOR;
        // Reflection: h ∝ wi + wo; refraction: h ∝ −(η_i wi + η_o wo) (Walter eq. 16).
        g.h = g.reflection ? Vector3f(wi + wo) : Vector3f(-(g.etaI * wi + g.etaO * wo));
        const float length = g.h.norm();
        if (length == 0.0f)
            return false;
        g.h /= length;
        if (g.h.z() < 0.0f)
            g.h = -g.h;
        // Both directions must lie on the sides of the microfacet that the side of the
        // macro-surface implies (Walter's χ⁺ terms).
        if (wi.dot(g.h) * cosI <= 0.0f || wo.dot(g.h) * cosO <= 0.0f)
            return false;
        return true;
    }

    TexturedMicrofacet m_roughness;
    float m_intIOR, m_extIOR;
};

NORI_REGISTER_CLASS(RoughDielectric, "roughdielectric");

} // namespace
} // namespace nori
