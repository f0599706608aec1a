/*
 * microfacet — Nori's rough plastic: a diffuse substrate under a Beckmann microfacet
 * reflection lobe (Walter et al. 2007), f = kd/π + ks·D(h)·F(h·wi)·G/(4 cos θi cos θo)
 * with ks = 1 − max(kd), so that the sum stays energy-conserving.
 *
 * Parameters:
 *   alpha   float/texture  0.1       Beckmann roughness (> 0)
 *   alphaU, alphaV  float/texture  —  anisotropic roughness along the shading frame's
 *                                    tangent and bitangent, instead of alpha
 *   remapRoughness  boolean  false   the roughness values are pbrt-v4's r, α = √r
 *   intIOR  float          1.5046    index of refraction of the coating
 *   extIOR  float          1.000277  index of refraction outside
 *   kd      color/texture  0.5       albedo of the diffuse substrate, in [0, 1]
 *
 *   <bsdf type="microfacet"><float name="alpha" value="0.2"/></bsdf>
 */
#include <nori/bsdf.h>
#include <nori/bsdfparams.h>
#include <nori/frame.h>
#include <nori/fresnel.h>
#include <nori/microfacet.h>
#include <nori/warp.h>

namespace nori {
namespace {

class Microfacet : public BSDF {
public:
    explicit Microfacet(const PropertyList &props)
        : m_roughness(MicrofacetDistribution::Type::Beckmann, props, m_textures, "microfacet") {
        m_intIOR = props.getFloat("intIOR", 1.5046f);
        m_extIOR = props.getFloat("extIOR", 1.000277f);
        m_kd = m_textures.color(props, "kd", Color3f(0.5f));
        const Color3f kd = m_kd->average();
        if (m_kd->isConstant() && ((kd < 0.0f).any() || (kd > 1.0f).any()))
            throw NoriException("microfacet: 'kd' must lie in [0, 1]");
    }

    Color3f eval(const BSDFQueryRecord &bRec) const override {
        if (!isFrontReflection(bRec))
            return Color3f(0.0f);
        const float cosI = Frame::cosTheta(bRec.wi), cosO = Frame::cosTheta(bRec.wo);
        const Lobes lobes = lobesAt(bRec);
        const Vector3f h = Vector3f(bRec.wi + bRec.wo).normalized();
        const float specular = lobes.distribution.D(h) *
                               fresnelDielectric(h.dot(bRec.wi), m_extIOR, m_intIOR) *
                               lobes.distribution.G(bRec.wi, bRec.wo, h) / (4.0f * cosI * cosO);
        return lobes.kd * kInvPi + Color3f(lobes.ks * specular);
    }

    float pdf(const BSDFQueryRecord &bRec) const override {
        if (!isFrontReflection(bRec))
            return 0.0f;
        const float cosO = Frame::cosTheta(bRec.wo);
        const Lobes lobes = lobesAt(bRec);
        const Vector3f h = Vector3f(bRec.wi + bRec.wo).normalized();
        // Mixture of the lobes; the reflected direction's density is the normal's
        // density times the Jacobian 1/(4 |wo·h|) (Walter eq. 14).
        const float specular = lobes.distribution.pdfNormal(h) / (4.0f * std::abs(h.dot(bRec.wo)));
        return lobes.ks * specular + (1.0f - lobes.ks) * cosO * kInvPi;
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        if (Frame::cosTheta(bRec.wi) <= 0.0f)
            return Color3f(0.0f);
        bRec.measure = ESolidAngle;
        bRec.eta = 1.0f;
        const Lobes lobes = lobesAt(bRec);
        if (sample.x() < lobes.ks) {
            // Reuse the sample: rescale the first coordinate to [0, 1).
            const Point2f reused(sample.x() / lobes.ks, sample.y());
            const Vector3f h = lobes.distribution.sampleNormal(reused);
            bRec.wo = reflect(bRec.wi, h);
        } else {
            const Point2f reused((sample.x() - lobes.ks) / (1.0f - lobes.ks), sample.y());
            bRec.wo = Warp::squareToCosineHemisphere(reused);
        }
        if (Frame::cosTheta(bRec.wo) <= 0.0f)
            return Color3f(0.0f);
        return sampleWeight(bRec);
    }

    bool isDiffuse() const override { return true; }

    std::string toString() const override {
        return fmt::format("Microfacet[{}, intIOR={}, extIOR={}, kd={}]", m_roughness.toString(),
                           m_intIOR, m_extIOR, m_kd->toString());
    }

private:
    /// The lobes at a point: kd and alpha from their textures, ks = 1 − max(kd).
    struct Lobes {
        Color3f kd;
        float ks;
        MicrofacetDistribution distribution;
    };
    Lobes lobesAt(const TextureQuery &q) const {
        const Color3f kd = m_kd->eval(q).max(0.0f).min(1.0f);
        return {kd, 1.0f - kd.maxCoeff(), m_roughness.at(q)};
    }

    TexturedMicrofacet m_roughness;
    std::shared_ptr<const Texture> m_kd;
    float m_intIOR, m_extIOR;
};

NORI_REGISTER_CLASS(Microfacet, "microfacet");

} // namespace
} // namespace nori
