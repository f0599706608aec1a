#include <nori/microfacet.h>
#include <nori/warp.h>

namespace nori {

MicrofacetDistribution::Type MicrofacetDistribution::parseType(const std::string &name) {
    if (name == "beckmann")
        return Type::Beckmann;
    if (name == "ggx")
        return Type::GGX;
    throw NoriException("unknown microfacet distribution '{}' (use 'beckmann' or 'ggx')", name);
}

float MicrofacetDistribution::D(const Vector3f &m) const {
    // The warps' densities are D(m) cos θm.
    if (m.z() <= 0.0f)
        return 0.0f;
    return pdfNormal(m) / m.z();
}

float MicrofacetDistribution::G1(const Vector3f &v, const Vector3f &m) const {
    // No shadowing from the back of a microfacet (Walter eq. 7's χ⁺ term).
    if (v.dot(m) * v.z() <= 0.0f)
        return 0.0f;
    const float cos2 = v.z() * v.z();
    const float tan2 = std::max(0.0f, 1.0f - cos2) / cos2;
    if (tan2 == 0.0f)
        return 1.0f;
    if (m_type == Type::GGX)
        return 2.0f / (1.0f + std::sqrt(1.0f + m_alpha * m_alpha * tan2));
    // Beckmann: Walter's rational approximation of the Smith integral, in a = 1/(α tan θ).
    const float a = 1.0f / (m_alpha * std::sqrt(tan2));
    if (a >= 1.6f)
        return 1.0f;
    return (3.535f * a + 2.181f * a * a) / (1.0f + 2.276f * a + 2.577f * a * a);
}

Vector3f MicrofacetDistribution::sampleNormal(const Point2f &sample) const {
    return m_type == Type::GGX ? Warp::squareToGGX(sample, m_alpha)
                               : Warp::squareToBeckmann(sample, m_alpha);
}

float MicrofacetDistribution::pdfNormal(const Vector3f &m) const {
    return m_type == Type::GGX ? Warp::squareToGGXPdf(m, m_alpha)
                               : Warp::squareToBeckmannPdf(m, m_alpha);
}

TexturedMicrofacet::TexturedMicrofacet(MicrofacetDistribution::Type type, const PropertyList &props,
                                       TextureParameters &textures, const std::string &plugin)
    : m_type(type), m_alpha(textures.scalar(props, "alpha", 0.1f)) {
    if (m_alpha->isConstant() && !(m_alpha->average().x() > 0.0f))
        throw NoriException("{}: 'alpha' must be positive, got {}", plugin, m_alpha->average().x());
}

} // namespace nori
