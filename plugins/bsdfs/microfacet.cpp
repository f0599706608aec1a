/*
 * microfacet — Nori's rough plastic: a diffuse substrate under a Beckmann microfacet
 * reflection lobe (Walter et al. 2007), f = kd/π + ks·D(h)·F(h·wi)·G/(4 cos θi cos θo)
 * with ks = 1 − max(kd), so that the sum stays energy-conserving.
 *
 * Parameters:
 *   alpha   float  0.1       Beckmann roughness
 *   intIOR  float  1.5046    index of refraction of the coating
 *   extIOR  float  1.000277  index of refraction outside
 *   kd      color  0.5       albedo of the diffuse substrate
 *
 *   <bsdf type="microfacet"><float name="alpha" value="0.2"/></bsdf>
 */
#include <nori/bsdf.h>
#include <nori/frame.h>
#include <nori/fresnel.h>
#include <nori/microfacet.h>
#include <nori/warp.h>

namespace nori {

class Microfacet : public BSDF {
public:
    explicit Microfacet(const PropertyList &props)
        : m_distribution(MicrofacetDistribution::Type::Beckmann, props.getFloat("alpha", 0.1f)) {
        m_intIOR = props.getFloat("intIOR", 1.5046f);
        m_extIOR = props.getFloat("extIOR", 1.000277f);
        m_kd = props.getColor("kd", Color3f(0.5f));
        if (!(m_distribution.alpha() > 0.0f))
            throw NoriException("microfacet: 'alpha' must be positive, got {}",
                                m_distribution.alpha());
        if ((m_kd < 0.0f).any() || (m_kd > 1.0f).any())
            throw NoriException("microfacet: 'kd' must lie in [0, 1]");
        m_ks = 1.0f - m_kd.maxCoeff();
    }

    Color3f eval(const BSDFQueryRecord &bRec) const override {
        const float cosI = Frame::cosTheta(bRec.wi), cosO = Frame::cosTheta(bRec.wo);
        if (bRec.measure != ESolidAngle || cosI <= 0.0f || cosO <= 0.0f)
            return Color3f(0.0f);
        const Vector3f h = Vector3f(bRec.wi + bRec.wo).normalized();
        const float specular = m_distribution.D(h) *
                               fresnelDielectric(h.dot(bRec.wi), m_extIOR, m_intIOR) *
                               m_distribution.G(bRec.wi, bRec.wo, h) / (4.0f * cosI * cosO);
        return m_kd * kInvPi + Color3f(m_ks * specular);
    }

    float pdf(const BSDFQueryRecord &bRec) const override {
        const float cosI = Frame::cosTheta(bRec.wi), cosO = Frame::cosTheta(bRec.wo);
        if (bRec.measure != ESolidAngle || cosI <= 0.0f || cosO <= 0.0f)
            return 0.0f;
        const Vector3f h = Vector3f(bRec.wi + bRec.wo).normalized();
        // Mixture of the lobes; the reflected direction's density is the normal's
        // density times the Jacobian 1/(4 |wo·h|) (Walter eq. 14).
        const float specular = m_distribution.pdfNormal(h) / (4.0f * std::abs(h.dot(bRec.wo)));
        return m_ks * specular + (1.0f - m_ks) * cosO * kInvPi;
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        if (Frame::cosTheta(bRec.wi) <= 0.0f)
            return Color3f(0.0f);
        bRec.measure = ESolidAngle;
        bRec.eta = 1.0f;
        if (sample.x() < m_ks) {
            // Reuse the sample: rescale the first coordinate to [0, 1).
            const Point2f reused(sample.x() / m_ks, sample.y());
            const Vector3f h = m_distribution.sampleNormal(reused);
            bRec.wo = reflect(bRec.wi, h);
        } else {
            const Point2f reused((sample.x() - m_ks) / (1.0f - m_ks), sample.y());
            bRec.wo = Warp::squareToCosineHemisphere(reused);
        }
        if (Frame::cosTheta(bRec.wo) <= 0.0f)
            return Color3f(0.0f);
        return sampleWeight(bRec);
    }

    bool isDiffuse() const override { return true; }

    std::string toString() const override {
        return fmt::format("Microfacet[alpha={}, intIOR={}, extIOR={}, kd=({}, {}, {})]",
                           m_distribution.alpha(), m_intIOR, m_extIOR, m_kd.r(), m_kd.g(),
                           m_kd.b());
    }

private:
    MicrofacetDistribution m_distribution;
    float m_intIOR, m_extIOR, m_ks;
    Color3f m_kd;
};

NORI_REGISTER_CLASS(Microfacet, "microfacet");

} // namespace nori
