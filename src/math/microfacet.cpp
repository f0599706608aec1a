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
    if (m.z() <= 0.0f)
        return 0.0f;
    if (isIsotropic())
        return pdfNormal(m) / m.z(); // the warps' densities are D(m) cos θm
    // The stretched forms (Heitz 2014, eq. 82 and 83), with e = tan²θ (cos²φ/αx² +
    // sin²φ/αy²) written through the components of the unit normal m.
    const float x = m.x() / m_alphaX, y = m.y() / m_alphaY, z2 = m.z() * m.z();
    if (m_type == Type::GGX) {
        const float root = x * x + y * y + z2;
        return 1.0f / (kPi * m_alphaX * m_alphaY * root * root);
    }
    return std::exp(-(x * x + y * y) / z2) / (kPi * m_alphaX * m_alphaY * z2 * z2);
}

float MicrofacetDistribution::projectedRoughness2Tan2(const Vector3f &v) const {
    const float x = v.x() * m_alphaX, y = v.y() * m_alphaY;
    return (x * x + y * y) / (v.z() * v.z());
}

float MicrofacetDistribution::lambda(const Vector3f &v) const {
    const float a2Tan2 = projectedRoughness2Tan2(v);
    if (!(a2Tan2 > 0.0f))
        return 0.0f;
    if (std::isinf(a2Tan2))
        return kInfinity;
    if (m_type == Type::GGX)
        return 0.5f * (std::sqrt(1.0f + a2Tan2) - 1.0f);
    const float a = 1.0f / std::sqrt(a2Tan2);
    if (a >= 1.6f)
        return 0.0f;
    return (1.0f - 1.259f * a + 0.396f * a * a) / (3.535f * a + 2.181f * a * a);
}

float MicrofacetDistribution::G1(const Vector3f &v, const Vector3f &m) const {
    // No shadowing from the back of a microfacet (Walter eq. 7's χ⁺ term).
    if (v.dot(m) * v.z() <= 0.0f)
        return 0.0f;
    const float a2Tan2 = projectedRoughness2Tan2(v);
    if (a2Tan2 == 0.0f)
        return 1.0f;
    if (m_type == Type::GGX)
        return 2.0f / (1.0f + std::sqrt(1.0f + a2Tan2));
    // Beckmann: Walter's rational approximation of the Smith integral, in a = 1/(α tan θ).
    const float a = 1.0f / std::sqrt(a2Tan2);
    if (a >= 1.6f)
        return 1.0f;
    return (3.535f * a + 2.181f * a * a) / (1.0f + 2.276f * a + 2.577f * a * a);
}

Vector3f MicrofacetDistribution::sampleNormal(const Point2f &sample) const {
    if (isIsotropic())
        return m_type == Type::GGX ? Warp::squareToGGX(sample, m_alphaX)
                                   : Warp::squareToBeckmann(sample, m_alphaX);
    // Stretch a normal of the unit-roughness distribution: its slopes (−x/z, −y/z) scale
    // by (αx, αy), which maps D₁(m) cos θm onto the anisotropic D(m) cos θm.
    const Vector3f unit = m_type == Type::GGX ? Warp::squareToGGX(sample, 1.0f)
                                              : Warp::squareToBeckmann(sample, 1.0f);
    return Vector3f(m_alphaX * unit.x(), m_alphaY * unit.y(), unit.z()).normalized();
}

float MicrofacetDistribution::pdfNormal(const Vector3f &m) const {
    if (isIsotropic())
        return m_type == Type::GGX ? Warp::squareToGGXPdf(m, m_alphaX)
                                   : Warp::squareToBeckmannPdf(m, m_alphaX);
    return D(m) * std::max(m.z(), 0.0f);
}

Vector3f MicrofacetDistribution::sampleNormal(const Vector3f &v, const Point2f &sample) const {
    if (m_type != Type::GGX)
        return sampleNormal(sample);
    // Heitz 2018, listing 1: stretch v to the unit-roughness configuration, sample the
    // projected area of a hemisphere as seen from it (a disk whose far half is squashed
    // by (1 + cos θ)/2), lift the point onto the hemisphere and unstretch the normal.
    const Vector3f stretched = Vector3f(m_alphaX * v.x(), m_alphaY * v.y(), v.z()).normalized();
    const float lengthSquared = stretched.x() * stretched.x() + stretched.y() * stretched.y();
    const Vector3f t1 = lengthSquared > 0.0f ? Vector3f(-stretched.y(), stretched.x(), 0.0f) /
                                                   std::sqrt(lengthSquared)
                                             : Vector3f(1.0f, 0.0f, 0.0f);
    const Vector3f t2 = stretched.cross(t1);
    const float r = std::sqrt(sample.x()), phi = 2.0f * kPi * sample.y();
    const float p1 = r * std::cos(phi);
    const float s = 0.5f * (1.0f + stretched.z());
    const float p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * r * std::sin(phi);
    const Vector3f onHemisphere =
        p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * stretched;
    return Vector3f(m_alphaX * onHemisphere.x(), m_alphaY * onHemisphere.y(),
                    std::max(1e-6f, onHemisphere.z()))
        .normalized();
}

float MicrofacetDistribution::pdfNormal(const Vector3f &v, const Vector3f &m) const {
    if (m_type != Type::GGX)
        return pdfNormal(m);
    // D_v(m) = G1(v, m) ⟨v, m⟩⁺ D(m)/cos θv (Heitz 2018, eq. 1).
    if (v.z() <= 0.0f)
        return 0.0f;
    const float cosVM = v.dot(m);
    if (cosVM <= 0.0f)
        return 0.0f;
    return G1(v, m) * cosVM * D(m) / v.z();
}

} // namespace nori
