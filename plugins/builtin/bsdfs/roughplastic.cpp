/*
 * roughplastic — a rough dielectric coating over a diffuse base, as Mitsuba 0.6 defines it
 * (Mitsuba 0.6 documentation, "roughplastic"; Weidlich and Wilkie 2007): the coating's
 * microfacet reflection s·F·D·G/(4 cos θi cos θo) (Walter et al. 2007), plus the base
 * seen through it, ρ/(1 − F_dr) · T(θi) T(θo)/(π η²), where T is the transmittance of the
 * rough interface (roughtransmittance.h) and F_dr = 1 − its diffuse transmittance from
 * inside. Samples the microfacet lobe with probability (1 − T)s/((1 − T)s + T(1 − s)),
 * s weighing the mean specular reflectance against the mean diffuse one, as Mitsuba does.
 * With alphaU ≠ alphaV, T is taken at the roughness the anisotropic surface shows in
 * wi's and wo's azimuths (Heitz 2014, eq. 80): an approximation, as Mitsuba has none.
 *
 * Parameters:
 *   distribution         string         "beckmann"  "beckmann" or "ggx"
 *   alpha                float          0.1       roughness, in (0, 1]
 *   alphaU, alphaV       float          alpha     roughness along the tangent and the
 *                                                 bitangent (anisotropic)
 *   intIOR               float          1.49      index of refraction of the coating, or a
 *                                                 name ("polypropylene", "bk7", ...)
 *   extIOR               float          1.000277  index of refraction outside, or a name
 *   diffuseReflectance   color/texture  0.5       albedo of the base, in [0, 1]
 *   specularReflectance  color/texture  1         scales the microfacet reflection
 *   nonlinear            boolean        false     true: ρ/(1 − ρ F_dr) instead of
 *                                                 ρ/(1 − F_dr)
 *
 *   <bsdf type="roughplastic"><float name="alpha" value="0.2"/>
 *       <color name="diffuseReflectance" value="0.7, 0.3, 0.1"/></bsdf>
 *
 *   <bsdf type="roughplastic"><string name="distribution" value="ggx"/>
 *       <float name="alphaU" value="0.05"/> <float name="alphaV" value="0.3"/>
 *       <boolean name="nonlinear" value="true"/></bsdf>
 */
#include <nori/bsdf.h>
#include <nori/bsdfparams.h>
#include <nori/frame.h>
#include <nori/fresnel.h>
#include <nori/roughtransmittance.h>
#include <nori/warp.h>

namespace nori {
namespace {

class RoughPlastic : public BSDF {
public:
    explicit RoughPlastic(const PropertyList &props)
        : m_type(MicrofacetDistribution::parseType(props.getString("distribution", "beckmann"))),
          m_layers(props, m_textures, "roughplastic") {
        const float alpha = props.getFloat("alpha", 0.1f);
        m_alphaU = props.getFloat("alphaU", alpha);
        m_alphaV = props.getFloat("alphaV", alpha);
        for (const float a : {alpha, m_alphaU, m_alphaV})
            if (!(a > 0.0f && a <= RoughTransmittance::kMaxAlpha))
                throw NoriException("roughplastic: the roughness ('alpha', 'alphaU', 'alphaV') "
                                    "must lie in (0, {}], got {}",
                                    RoughTransmittance::kMaxAlpha, a);
        const float eta = m_layers.intIOR / m_layers.extIOR;
        m_external = &RoughTransmittance::get(m_type, eta);
        // F_dr of the coating seen from inside at the roughness of the base's light: for an
        // anisotropic coating, at the mean of the two.
        m_fdrInternal =
            1.0f -
            RoughTransmittance::get(m_type, 1.0f / eta).diffuse(std::sqrt(m_alphaU * m_alphaV));
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        const float cosI = Frame::cosTheta(bRec.wi);
        if (cosI <= 0.0f)
            return Color3f(0.0f);
        const float specularProbability = specularProbabilityAt(bRec.wi);
        bRec.measure = ESolidAngle;
        bRec.eta = 1.0f;
        if (sample.x() < specularProbability) {
            const Point2f reused(sample.x() / specularProbability, sample.y());
            const Vector3f m = distribution().sampleNormal(bRec.wi, reused);
            bRec.wo = reflect(bRec.wi, m);
        } else {
            const Point2f reused((sample.x() - specularProbability) / (1.0f - specularProbability),
                                 sample.y());
            bRec.wo = Warp::squareToCosineHemisphere(reused);
        }
        if (Frame::cosTheta(bRec.wo) <= 0.0f)
            return Color3f(0.0f);
        return sampleWeight(bRec);
    }

    Color3f eval(const BSDFQueryRecord &bRec) const override {
        if (!isFrontReflection(bRec))
            return Color3f(0.0f);
        const MicrofacetDistribution d = distribution();
        const float cosI = Frame::cosTheta(bRec.wi), cosO = Frame::cosTheta(bRec.wo);
        const Vector3f h = Vector3f(bRec.wi + bRec.wo).normalized();
        const float specular = fresnelDielectric(h.dot(bRec.wi), m_layers.extIOR, m_layers.intIOR) *
                               d.D(h) * d.G(bRec.wi, bRec.wo, h) / (4.0f * cosI * cosO);
        const float throughCoating =
            transmittance(bRec.wi) * transmittance(bRec.wo) * m_layers.invEta2 * kInvPi;
        return m_layers.specularReflectance(bRec) * specular +
               m_layers.baseReflectance(bRec, m_fdrInternal) * throughCoating;
    }

    float pdf(const BSDFQueryRecord &bRec) const override {
        if (!isFrontReflection(bRec))
            return 0.0f;
        const float specularProbability = specularProbabilityAt(bRec.wi);
        const Vector3f h = Vector3f(bRec.wi + bRec.wo).normalized();
        // The visible normal's density times the reflection Jacobian 1/(4 wo·h).
        const float specular =
            distribution().pdfNormal(bRec.wi, h) / (4.0f * std::abs(h.dot(bRec.wo)));
        return specularProbability * specular +
               (1.0f - specularProbability) * Warp::squareToCosineHemispherePdf(bRec.wo);
    }

    bool isDiffuse() const override { return true; }

    std::string toString() const override {
        return fmt::format("RoughPlastic[distribution={}, alphaU={}, alphaV={}, {}]",
                           m_type == MicrofacetDistribution::Type::GGX ? "ggx" : "beckmann",
                           m_alphaU, m_alphaV, m_layers.toString());
    }

private:
    MicrofacetDistribution distribution() const {
        return MicrofacetDistribution(m_type, m_alphaU, m_alphaV);
    }

    /// The transmittance of the coating toward w (w.z > 0), at the roughness the surface
    /// shows in w's azimuth: √(cos²φ αU² + sin²φ αV²).
    float transmittance(const Vector3f &w) const {
        float alpha = m_alphaU;
        if (m_alphaU != m_alphaV) {
            const float sin2 = w.x() * w.x() + w.y() * w.y();
            const float cos2Phi = sin2 > 0.0f ? w.x() * w.x() / sin2 : 1.0f;
            alpha =
                std::sqrt(cos2Phi * m_alphaU * m_alphaU + (1.0f - cos2Phi) * m_alphaV * m_alphaV);
        }
        return (*m_external)(Frame::cosTheta(w), alpha);
    }

    /// Mitsuba's probability of the microfacet lobe: by its share 1 − T(θi).
    float specularProbabilityAt(const Vector3f &wi) const {
        return m_layers.specularProbability(1.0f - transmittance(wi));
    }

    MicrofacetDistribution::Type m_type;
    PlasticLayers m_layers;
    float m_alphaU, m_alphaV;
    float m_fdrInternal;
    const RoughTransmittance *m_external;
};

NORI_REGISTER_CLASS(RoughPlastic, "roughplastic");

} // namespace
} // namespace nori
