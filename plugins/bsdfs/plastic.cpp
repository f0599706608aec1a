/*
 * plastic — a smooth dielectric coating over a diffuse base, as Mitsuba 0.6 defines it
 * (Mitsuba 0.6 documentation, "plastic"; Weidlich and Wilkie 2007): the coating
 * reflects F(θi) specularly; the rest enters, is scattered by the base and leaves through
 * the coating, so the diffuse term is ρ/(1 − F_dr) · (1 − F(θi))(1 − F(θo))/(π η²), where
 * F_dr is the Fresnel diffuse reflectance of the coating seen from inside: the light the
 * base scatters is reflected back to it again and again (d'Eon and Irving 2011).
 * Samples the specular lobe with probability F·s/(F·s + (1 − F)(1 − s)), where s weighs
 * the mean specular reflectance against the mean diffuse one, as Mitsuba does.
 *
 * Parameters:
 *   intIOR               float          1.49      index of refraction of the coating, or a
 *                                                 name ("polypropylene", "bk7", "water", ...)
 *   extIOR               float          1.000277  index of refraction outside, or a name
 *   diffuseReflectance   color/texture  0.5       albedo of the base, in [0, 1]
 *   specularReflectance  color/texture  1         scales the specular reflection (not
 *                                                 physical below 1, but Mitsuba's)
 *   nonlinear            boolean        false     true: the base's interreflections
 *                                                 change its colour, ρ/(1 − ρ F_dr)
 *                                                 instead of ρ/(1 − F_dr)
 *
 *   <bsdf type="plastic"><color name="diffuseReflectance" value="0.1, 0.3, 0.6"/></bsdf>
 *
 *   <bsdf type="plastic">
 *       <string name="intIOR" value="bk7"/> <boolean name="nonlinear" value="true"/>
 *       <color name="diffuseReflectance" value="0.8"/>
 *   </bsdf>
 */
#include <nori/bsdf.h>
#include <nori/bsdfparams.h>
#include <nori/frame.h>
#include <nori/fresnel.h>
#include <nori/warp.h>

namespace nori {
namespace {

class Plastic : public BSDF {
public:
    explicit Plastic(const PropertyList &props) {
        m_intIOR = readIOR(props, "intIOR", 1.49f, "plastic");
        m_extIOR = readIOR(props, "extIOR", 1.000277f, "plastic");
        if (m_intIOR == m_extIOR)
            throw NoriException("plastic: 'intIOR' and 'extIOR' must differ, both are {}",
                                m_intIOR);
        m_diffuse = m_textures.color(props, "diffuseReflectance", Color3f(0.5f));
        m_specular = m_textures.color(props, "specularReflectance", Color3f(1.0f));
        m_nonlinear = props.getBoolean("nonlinear", false);
        const float eta = m_intIOR / m_extIOR;
        m_invEta2 = 1.0f / (eta * eta);
        // The base sees the coating from inside (relative index 1/η); the outside sees
        // it with η. (1/η²)(1 − F_dr(η)) = 1 − F_dr(1/η) makes the diffuse albedo ρ(1 − F).
        m_fdrInternal = fresnelDiffuseReflectance(1.0f / eta);
        m_fdrExternal = fresnelDiffuseReflectance(eta);
        const float diffuseMean = m_diffuse->average().getLuminance();
        const float specularMean = m_specular->average().getLuminance();
        m_specularSamplingWeight =
            diffuseMean + specularMean > 0.0f ? specularMean / (diffuseMean + specularMean) : 0.5f;
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        const float cosI = Frame::cosTheta(bRec.wi);
        if (cosI <= 0.0f)
            return Color3f(0.0f);
        const float fresnelI = fresnel(cosI);
        const float specularProbability = specularProbabilityAt(fresnelI);
        bRec.eta = 1.0f;
        if (sample.x() < specularProbability) {
            // The coating's mirror reflection, chosen with probability P: weight s·F/P.
            bRec.measure = EDiscrete;
            bRec.wo = Vector3f(-bRec.wi.x(), -bRec.wi.y(), bRec.wi.z());
            return specularReflectance(bRec) * (fresnelI / specularProbability);
        }
        const Point2f reused((sample.x() - specularProbability) / (1.0f - specularProbability),
                             sample.y());
        bRec.measure = ESolidAngle;
        bRec.wo = Warp::squareToCosineHemisphere(reused);
        if (Frame::cosTheta(bRec.wo) <= 0.0f)
            return Color3f(0.0f);
        // f·cos/pdf = ρ'(1 − Fi)(1 − Fo)/(π η²) · cos / ((1 − P) cos/π).
        return baseReflectance(bRec) *
               ((1.0f - fresnelI) * (1.0f - fresnel(Frame::cosTheta(bRec.wo))) * m_invEta2 /
                (1.0f - specularProbability));
    }

    Color3f eval(const BSDFQueryRecord &bRec) const override {
        if (!isFrontReflection(bRec))
            return Color3f(0.0f);
        const float fresnelI = fresnel(Frame::cosTheta(bRec.wi));
        const float fresnelO = fresnel(Frame::cosTheta(bRec.wo));
        return baseReflectance(bRec) * ((1.0f - fresnelI) * (1.0f - fresnelO) * m_invEta2 * kInvPi);
    }

    float pdf(const BSDFQueryRecord &bRec) const override {
        if (!isFrontReflection(bRec))
            return 0.0f;
        const float specularProbability = specularProbabilityAt(fresnel(Frame::cosTheta(bRec.wi)));
        return (1.0f - specularProbability) * Warp::squareToCosineHemispherePdf(bRec.wo);
    }

    bool isDiffuse() const override { return true; }

    /// In closed form: s·F(θi) reflected by the coating, and ρ'(1 − F(θi))(1 − F_dr(η))/η²
    /// leaving through it (the cosine-weighted integral of (1 − F(θo))).
    Color3f albedo(const BSDFQueryRecord &bRec) const override {
        const float cosI = Frame::cosTheta(bRec.wi);
        if (cosI <= 0.0f)
            return Color3f(0.0f);
        const float fresnelI = fresnel(cosI);
        return specularReflectance(bRec) * fresnelI +
               baseReflectance(bRec) * ((1.0f - fresnelI) * (1.0f - m_fdrExternal) * m_invEta2);
    }

    std::string toString() const override {
        return fmt::format("Plastic[intIOR={}, extIOR={}, diffuseReflectance={}, "
                           "specularReflectance={}, nonlinear={}]",
                           m_intIOR, m_extIOR, m_diffuse->toString(), m_specular->toString(),
                           m_nonlinear);
    }

private:
    float fresnel(float cosTheta) const { return fresnelDielectric(cosTheta, m_extIOR, m_intIOR); }

    /// Mitsuba's probability of the specular lobe for a Fresnel reflectance F.
    float specularProbabilityAt(float fresnelI) const {
        const float specular = fresnelI * m_specularSamplingWeight;
        const float diffuse = (1.0f - fresnelI) * (1.0f - m_specularSamplingWeight);
        return specular + diffuse > 0.0f ? specular / (specular + diffuse) : 0.0f;
    }

    Color3f specularReflectance(const TextureQuery &q) const {
        return m_specular->eval(q).max(0.0f);
    }

    /// ρ' = ρ/(1 − F_dr), or ρ/(1 − ρ F_dr) when nonlinear: the base with its
    /// interreflections under the coating summed as a geometric series.
    Color3f baseReflectance(const TextureQuery &q) const {
        const Color3f rho = m_diffuse->eval(q).max(0.0f).min(1.0f);
        if (m_nonlinear)
            return rho / (Color3f(1.0f) - rho * m_fdrInternal);
        return rho / (1.0f - m_fdrInternal);
    }

    float m_intIOR, m_extIOR;
    std::shared_ptr<const Texture> m_diffuse, m_specular;
    bool m_nonlinear;
    float m_invEta2, m_fdrInternal, m_fdrExternal, m_specularSamplingWeight;
};

NORI_REGISTER_CLASS(Plastic, "plastic");

} // namespace
} // namespace nori
