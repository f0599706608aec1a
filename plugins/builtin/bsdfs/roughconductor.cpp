/*
 * roughconductor — a rough metal: microfacet reflection f = D·F·G/(4 cos θi cos θo)
 * with the conductor Fresnel term (Walter et al. 2007, eq. 20), Beckmann or GGX.
 *
 * Parameters:
 *   distribution  string  "ggx"   "beckmann" or "ggx"
 *   alpha         float/texture  0.1     roughness (> 0)
 *   alphaU, alphaV  float/texture  —     anisotropic roughness along the shading frame's
 *                                 tangent and bitangent, instead of alpha
 *   remapRoughness  boolean  false  the roughness values are pbrt-v4's r, α = √r
 *   material      string  —       a named metal: Au, Ag, Cu, Al, Cr, CuZn, W, none, … (every
 *                                 name of Mitsuba 0.6 and pbrt-v4; instead of eta and k)
 *   eta, k        color/texture  copper  complex index of refraction
 *   extIOR        float   1.000277  index of refraction of the outside
 *
 *   <bsdf type="roughconductor"><string name="material" value="Al"/>
 *       <float name="alpha" value="0.3"/></bsdf>
 */
#include <nori/bsdf.h>
#include <nori/bsdfparams.h>
#include <nori/frame.h>
#include <nori/fresnel.h>
#include <nori/microfacet.h>

namespace nori {
namespace {

class RoughConductor : public BSDF {
public:
    explicit RoughConductor(const PropertyList &props)
        : m_roughness(MicrofacetDistribution::parseType(props.getString("distribution", "ggx")),
                      props, m_textures, "roughconductor") {
        m_ior = readConductorIOR(props, "roughconductor", m_textures);
    }

    Color3f eval(const BSDFQueryRecord &bRec) const override {
        const MicrofacetDistribution distribution = m_roughness.at(bRec);
        if (!isFrontReflection(bRec))
            return Color3f(0.0f);
        const float cosI = Frame::cosTheta(bRec.wi), cosO = Frame::cosTheta(bRec.wo);
        const Vector3f h = Vector3f(bRec.wi + bRec.wo).normalized();
        return m_ior.fresnel(bRec, h.dot(bRec.wi)) *
               (distribution.D(h) * distribution.G(bRec.wi, bRec.wo, h) / (4.0f * cosI * cosO));
    }

    float pdf(const BSDFQueryRecord &bRec) const override {
        const MicrofacetDistribution distribution = m_roughness.at(bRec);
        if (!isFrontReflection(bRec))
            return 0.0f;
        const Vector3f h = Vector3f(bRec.wi + bRec.wo).normalized();
        // Normal density times the reflection Jacobian 1/(4 |wo·h|) (Walter eq. 14).
        return distribution.pdfNormal(h) / (4.0f * std::abs(h.dot(bRec.wo)));
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        const MicrofacetDistribution distribution = m_roughness.at(bRec);
        if (Frame::cosTheta(bRec.wi) <= 0.0f)
            return Color3f(0.0f);
        const Vector3f h = distribution.sampleNormal(sample);
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
        return fmt::format("RoughConductor[distribution={}, {}]",
                           m_roughness.type() == MicrofacetDistribution::Type::GGX ? "ggx"
                                                                                   : "beckmann",
                           m_roughness.toString());
    }

private:
    TexturedMicrofacet m_roughness;
    ConductorIOR m_ior;
};

NORI_REGISTER_CLASS(RoughConductor, "roughconductor");

} // namespace
} // namespace nori
