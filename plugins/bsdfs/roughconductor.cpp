/*
 * roughconductor — a rough metal: microfacet reflection f = D·F·G/(4 cos θi cos θo)
 * with the conductor Fresnel term (Walter et al. 2007, eq. 20), Beckmann or GGX.
 *
 * Parameters:
 *   distribution  string  "ggx"   "beckmann" or "ggx"
 *   alpha         float   0.1     roughness (> 0)
 *   material      string  —       a named metal: Au, Ag, Cu, Al (instead of eta and k)
 *   eta, k        color   copper  complex index of refraction
 *   extIOR        float   1.000277  index of refraction of the outside
 *
 *   <bsdf type="roughconductor"><string name="material" value="Al"/>
 *       <float name="alpha" value="0.3"/></bsdf>
 */
#include <nori/bsdf.h>
#include <nori/frame.h>
#include <nori/fresnel.h>
#include <nori/microfacet.h>

namespace nori {

class RoughConductor : public BSDF {
public:
    explicit RoughConductor(const PropertyList &props)
        : m_distribution(MicrofacetDistribution::parseType(props.getString("distribution", "ggx")),
                         props.getFloat("alpha", 0.1f)) {
        if (!(m_distribution.alpha() > 0.0f))
            throw NoriException("roughconductor: 'alpha' must be positive, got {}",
                                m_distribution.alpha());
        readConductorIOR(props, "roughconductor", m_eta, m_k);
    }

    Color3f eval(const BSDFQueryRecord &bRec) const override {
        const float cosI = Frame::cosTheta(bRec.wi), cosO = Frame::cosTheta(bRec.wo);
        if (bRec.measure != ESolidAngle || cosI <= 0.0f || cosO <= 0.0f)
            return Color3f(0.0f);
        const Vector3f h = Vector3f(bRec.wi + bRec.wo).normalized();
        return fresnelConductor(h.dot(bRec.wi), m_eta, m_k) *
               (m_distribution.D(h) * m_distribution.G(bRec.wi, bRec.wo, h) / (4.0f * cosI * cosO));
    }

    float pdf(const BSDFQueryRecord &bRec) const override {
        if (bRec.measure != ESolidAngle || Frame::cosTheta(bRec.wi) <= 0.0f ||
            Frame::cosTheta(bRec.wo) <= 0.0f)
            return 0.0f;
        const Vector3f h = Vector3f(bRec.wi + bRec.wo).normalized();
        // Normal density times the reflection Jacobian 1/(4 |wo·h|) (Walter eq. 14).
        return m_distribution.pdfNormal(h) / (4.0f * std::abs(h.dot(bRec.wo)));
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        if (Frame::cosTheta(bRec.wi) <= 0.0f)
            return Color3f(0.0f);
        const Vector3f h = m_distribution.sampleNormal(sample);
        bRec.wo = reflect(bRec.wi, h);
        bRec.measure = ESolidAngle;
        bRec.eta = 1.0f;
        if (Frame::cosTheta(bRec.wo) <= 0.0f)
            return Color3f(0.0f);
        return sampleWeight(bRec);
    }

    /// Not a delta distribution, so integrators should sample lights here too.
    bool isDiffuse() const override { return true; }

    std::string toString() const override {
        return fmt::format("RoughConductor[distribution={}, alpha={}]",
                           m_distribution.type() == MicrofacetDistribution::Type::GGX ? "ggx"
                                                                                      : "beckmann",
                           m_distribution.alpha());
    }

private:
    MicrofacetDistribution m_distribution;
    Color3f m_eta, m_k;
};

NORI_REGISTER_CLASS(RoughConductor, "roughconductor");

} // namespace nori
