// Microfacet distributions for rough surfaces (Walter et al. 2007, "Microfacet Models
// for Refraction through Rough Surfaces"): Beckmann and GGX with the Smith shadowing
// term, isotropic or anisotropic by stretching the slopes by αx along +x and αy along
// +y (Heitz 2014, "Understanding the Masking-Shadowing Function", §5.3). Directions and
// normals are in the local frame (macro-normal +z).
#pragma once

#include <nori/vector.h>

#include <string>

namespace nori {

class MicrofacetDistribution {
public:
    enum class Type { Beckmann, GGX };

    /// An isotropic distribution of roughness alpha.
    MicrofacetDistribution(Type type, float alpha) : MicrofacetDistribution(type, alpha, alpha) {}
    /// An anisotropic distribution: roughness alphaX along the local +x, alphaY along +y.
    MicrofacetDistribution(Type type, float alphaX, float alphaY)
        : m_type(type), m_alphaX(alphaX), m_alphaY(alphaY) {}
    /// "beckmann" or "ggx"; throws NoriException otherwise.
    static Type parseType(const std::string &name);

    Type type() const { return m_type; }
    float alphaX() const { return m_alphaX; }
    float alphaY() const { return m_alphaY; }
    bool isIsotropic() const { return m_alphaX == m_alphaY; }

    /// The normal distribution D(m), normalised so that ∫ D(m) cos θm dωm = 1.
    float D(const Vector3f &m) const;
    /// Smith's monodirectional shadowing G1(v, m) (Walter eq. 27 for Beckmann, 34 for GGX),
    /// with the roughness of the stretched distribution in v's azimuth (Heitz 2014, eq. 80).
    float G1(const Vector3f &v, const Vector3f &m) const;
    /// Smith's Λ(v), the ratio of a direction's masked to its visible projected microfacet
    /// area, on either side (Heitz 2014, eq. 86 for GGX, (√(1 + α² tan²θ) − 1)/2; for
    /// Beckmann, Walter et al.'s rational fit of its erf form). G1 = 1/(1 + Λ).
    float lambda(const Vector3f &v) const;
    /// G(wi, wo, m) = G1(wi, m) G1(wo, m).
    float G(const Vector3f &wi, const Vector3f &wo, const Vector3f &m) const {
        return G1(wi, m) * G1(wo, m);
    }
    /// A normal drawn with density D(m) cos θm.
    Vector3f sampleNormal(const Point2f &sample) const;
    /// The density of sampleNormal: D(m) cos θm.
    float pdfNormal(const Vector3f &m) const;

    /// A normal as seen from v (v.z > 0): for GGX, drawn from the distribution of visible
    /// normals G1(v) ⟨v, m⟩⁺ D(m)/cos θv (Heitz 2018, "Sampling the GGX Distribution of
    /// Visible Normals"), which wastes no samples on normals facing away from v; for
    /// Beckmann, whose visible normals have no closed-form inverse, sampleNormal().
    Vector3f sampleNormal(const Vector3f &v, const Point2f &sample) const;
    /// The density of sampleNormal(v, ·).
    float pdfNormal(const Vector3f &v, const Vector3f &m) const;

private:
    /// α² tan²θv in v's azimuth: the argument of Smith's Λ for the stretched distribution.
    float projectedRoughness2Tan2(const Vector3f &v) const;

    Type m_type;
    float m_alphaX, m_alphaY;
};

} // namespace nori
