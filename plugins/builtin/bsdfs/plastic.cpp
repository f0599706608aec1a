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
    explicit Plastic(const PropertyList &props) : m_layers(props, m_textures, "plastic") {
        // The base sees the coating from inside (relative index 1/η); the outside sees
        // it with η. (1/η²)(1 − F_dr(η)) = 1 − F_dr(1/η) makes the diffuse albedo ρ(1 − F).
        const float eta = m_layers.intIOR / m_layers.extIOR;
        m_fdrInternal = fresnelDiffuseReflectance(1.0f / eta);
        m_fdrExternal = fresnelDiffuseReflectance(eta);
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        const float cosI = Frame::cosTheta(bRec.wi);
        if (cosI <= 0.0f)
            return Color3f(0.0f);
        const float fresnelI = fresnel(cosI);
        const float specularProbability = m_layers.specularProbability(fresnelI);
        bRec.eta = 1.0f;
        if (sample.x() < specularProbability) {
            // The coating's mirror reflection, chosen with probability P: weight s·F/P.
            bRec.measure = EDiscrete;
            bRec.wo = Vector3f(-bRec.wi.x(), -bRec.wi.y(), bRec.wi.z());
            return m_layers.specularReflectance(bRec) * (fresnelI / specularProbability);
        }
        const Point2f reused((sample.x() - specularProbability) / (1.0f - specularProbability),
                             sample.y());
        bRec.measure = ESolidAngle;
        bRec.wo = Warp::squareToCosineHemisphere(reused);
        if (Frame::cosTheta(bRec.wo) <= 0.0f)
            return Color3f(0.0f);
        // f·cos/pdf = ρ'(1 − Fi)(1 − Fo)/(π η²) · cos / ((1 − P) cos/π).
        return m_layers.baseReflectance(bRec, m_fdrInternal) *
               ((1.0f - fresnelI) * (1.0f - fresnel(Frame::cosTheta(bRec.wo))) * m_layers.invEta2 /
                (1.0f - specularProbability));
    }

    Color3f eval(const BSDFQueryRecord &bRec) const override {
        if (!isFrontReflection(bRec))
            return Color3f(0.0f);
        const float fresnelI = fresnel(Frame::cosTheta(bRec.wi));
        const float fresnelO = fresnel(Frame::cosTheta(bRec.wo));
        return m_layers.baseReflectance(bRec, m_fdrInternal) *
               ((1.0f - fresnelI) * (1.0f - fresnelO) * m_layers.invEta2 * kInvPi);
    }

    float pdf(const BSDFQueryRecord &bRec) const override {
        if (!isFrontReflection(bRec))
            return 0.0f;
        const float specularProbability =
            m_layers.specularProbability(fresnel(Frame::cosTheta(bRec.wi)));
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
        return m_layers.specularReflectance(bRec) * fresnelI +
               m_layers.baseReflectance(bRec, m_fdrInternal) *
                   ((1.0f - fresnelI) * (1.0f - m_fdrExternal) * m_layers.invEta2);
    }

    std::string toString() const override {
        return fmt::format("Plastic[{}]", m_layers.toString());
    }

private:
    float fresnel(float cosTheta) const {
        return fresnelDielectric(cosTheta, m_layers.extIOR, m_layers.intIOR);
    }

    PlasticLayers m_layers;
    float m_fdrInternal, m_fdrExternal;
};

NORI_REGISTER_CLASS(Plastic, "plastic");

} // namespace
} // namespace nori
