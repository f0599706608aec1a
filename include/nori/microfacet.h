// Microfacet distributions for rough surfaces (Walter et al. 2007, "Microfacet Models
// for Refraction through Rough Surfaces"): Beckmann and GGX with the Smith shadowing
// term. Directions and normals are in the local frame (macro-normal +z).
#pragma once

#include <nori/vector.h>

#include <string>

namespace nori {

class MicrofacetDistribution {
public:
    enum class Type { Beckmann, GGX };

    MicrofacetDistribution(Type type, float alpha) : m_type(type), m_alpha(alpha) {}
    /// "beckmann" or "ggx"; throws NoriException otherwise.
    static Type parseType(const std::string &name);

    Type type() const { return m_type; }
    float alpha() const { return m_alpha; }

    /// The normal distribution D(m), normalised so that ∫ D(m) cos θm dωm = 1.
    float D(const Vector3f &m) const;
    /// Smith's monodirectional shadowing G1(v, m) (Walter eq. 27 for Beckmann, 34 for GGX).
    float G1(const Vector3f &v, const Vector3f &m) const;
    /// G(wi, wo, m) = G1(wi, m) G1(wo, m).
    float G(const Vector3f &wi, const Vector3f &wo, const Vector3f &m) const {
        return G1(wi, m) * G1(wo, m);
    }
    /// A normal drawn with density D(m) cos θm.
    Vector3f sampleNormal(const Point2f &sample) const;
    /// The density of sampleNormal: D(m) cos θm.
    float pdfNormal(const Vector3f &m) const;

private:
    Type m_type;
    float m_alpha;
};

} // namespace nori
