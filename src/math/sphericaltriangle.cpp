#include <nori/sphericaltriangle.h>

#include <algorithm>
#include <cmath>

namespace nori {

namespace {

/// The angle between two unit vectors, accurate near 0 and π where acos(dot) is not:
/// 2·asin(|u − v|/2) (PBR 4th ed. §3.3.2).
float angleBetween(const Vector3f &u, const Vector3f &v) {
    if (u.dot(v) < 0.0f)
        return kPi - 2.0f * std::asin(std::min(1.0f, (u + v).norm() / 2.0f));
    return 2.0f * std::asin(std::min(1.0f, (v - u).norm() / 2.0f));
}

/// The unit vector along the part of v perpendicular to the unit vector w.
Vector3f perpendicularPart(const Vector3f &v, const Vector3f &w) {
    return (v - v.dot(w) * w).normalized();
}

} // namespace

float sphericalTriangleSolidAngle(const Point3f &p0, const Point3f &p1, const Point3f &p2,
                                  const Point3f &ref) {
    const Vector3f a = (p0 - ref).normalized(), b = (p1 - ref).normalized(),
                   c = (p2 - ref).normalized();
    const float omega =
        2.0f * std::atan2(std::abs(a.dot(b.cross(c))), 1.0f + a.dot(b) + b.dot(c) + c.dot(a));
    return std::isfinite(omega) ? std::abs(omega) : 0.0f;
}

std::optional<Point2f> sampleSphericalTriangle(const Point3f &p0, const Point3f &p1,
                                               const Point3f &p2, const Point3f &ref,
                                               const Point2f &sample) {
    const Vector3f a = (p0 - ref).normalized(), b = (p1 - ref).normalized(),
                   c = (p2 - ref).normalized();
    // The great circles through each pair of vertices, by their normals; the triangle's
    // angle at a vertex is the angle between the two circles that meet there.
    Vector3f nAB = a.cross(b), nBC = b.cross(c), nCA = c.cross(a);
    if (!(nAB.squaredNorm() > 0.0f && nBC.squaredNorm() > 0.0f && nCA.squaredNorm() > 0.0f))
        return std::nullopt;
    nAB.normalize();
    nBC.normalize();
    nCA.normalize();
    const float alpha = angleBetween(nAB, -nCA), beta = angleBetween(nBC, -nAB),
                gamma = angleBetween(nCA, -nBC);
    const float area = alpha + beta + gamma - kPi; // Girard's theorem
    if (!(area > 0.0f))
        return std::nullopt;

    // Arvo's step 1: the sub-triangle (a, b, c′) of area Â = u·Ω has its vertex c′ on the
    // arc from a to c at cos(arc a c′) = q, with s, t = sin, cos (Â − α) and cos(arc a b).
    const float areaSub = sample.x() * area;
    const float s = std::sin(areaSub - alpha), t = std::cos(areaSub - alpha);
    const float cosAlpha = std::cos(alpha), sinAlpha = std::sin(alpha);
    const float u = t - cosAlpha, v = s + sinAlpha * a.dot(b);
    const float q =
        std::clamp(((v * t - u * s) * cosAlpha - v) / ((v * s + u * t) * sinAlpha), -1.0f, 1.0f);
    const Vector3f cPrime = q * a + safeSqrt(1.0f - q * q) * perpendicularPart(c, a);

    // Step 2: a point on the arc from b to c′, with cos θ to b uniform between 1 and b·c′.
    const float z = 1.0f - sample.y() * (1.0f - cPrime.dot(b));
    const Vector3f w = z * b + safeSqrt(1.0f - z * z) * perpendicularPart(cPrime, b);

    // Where the ray ref + t·w meets the triangle's plane (Möller and Trumbore 1997).
    const Vector3f e1 = p1 - p0, e2 = p2 - p0;
    const Vector3f s1 = w.cross(e2);
    const float divisor = s1.dot(e1);
    if (!(divisor != 0.0f) || !w.allFinite())
        return std::nullopt;
    const Vector3f fromP0 = ref - p0;
    float b1 = std::clamp(fromP0.dot(s1) / divisor, 0.0f, 1.0f);
    float b2 = std::clamp(w.dot(fromP0.cross(e1)) / divisor, 0.0f, 1.0f);
    if (b1 + b2 > 1.0f) {
        const float sum = b1 + b2;
        b1 /= sum;
        b2 /= sum;
    }
    return Point2f(b1, b2);
}

} // namespace nori
