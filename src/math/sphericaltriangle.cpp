#include <nori/sphericaltriangle.h>

#include <algorithm>
#include <cmath>

namespace nori {

namespace {

/// The unit vector along the part of v perpendicular to the unit vector w.
Vector3f perpendicularPart(const Vector3f &v, const Vector3f &w) {
    return (v - v.dot(w) * w).normalized();
}

} // namespace

SphericalTriangle::SphericalTriangle(const Vector3f &a, const Vector3f &b, const Vector3f &c)
    : a(a), b(b), c(c) {
    const float omega =
        2.0f * std::atan2(std::abs(a.dot(b.cross(c))), 1.0f + a.dot(b) + b.dot(c) + c.dot(a));
    solidAngle = std::isfinite(omega) ? std::abs(omega) : 0.0f;
}

float sphericalTriangleSolidAngle(const Point3f &p0, const Point3f &p1, const Point3f &p2,
                                  const Point3f &ref) {
    return SphericalTriangle((p0 - ref).normalized(), (p1 - ref).normalized(),
                             (p2 - ref).normalized())
        .solidAngle;
}

std::optional<Vector3f> sampleSphericalTriangle(const SphericalTriangle &triangle,
                                                const Point2f &sample) {
    const Vector3f &a = triangle.a, &b = triangle.b, &c = triangle.c;
    // The angle α at a is the angle between the arcs' tangents there, which a × b and
    // a × c are, turned by 90° about a: cos α from their dot product, sin α from their
    // cross product, (a × b) × (a × c) = (a·(b × c))·a, over the same lengths.
    const Vector3f ab = a.cross(b), ac = a.cross(c);
    const float lengths = ab.norm() * ac.norm();
    if (!(lengths > 0.0f) || !(triangle.solidAngle > 0.0f))
        return std::nullopt;
    const float cosAlpha = std::clamp(ab.dot(ac) / lengths, -1.0f, 1.0f);
    const float sinAlpha = std::min(std::abs(a.dot(b.cross(c))) / lengths, 1.0f);

    // Arvo's step 1: the sub-triangle (a, b, c′) of area Â = u·Ω has its vertex c′ on the
    // arc from a to c at cos(arc a c′) = q, with s, t = sin, cos (Â − α) and cos(arc a b).
    const float areaSub = sample.x() * triangle.solidAngle;
    const float sinArea = std::sin(areaSub), cosArea = std::cos(areaSub);
    const float s = sinArea * cosAlpha - cosArea * sinAlpha;
    const float t = cosArea * cosAlpha + sinArea * sinAlpha;
    const float u = t - cosAlpha, v = s + sinAlpha * a.dot(b);
    const float q =
        std::clamp(((v * t - u * s) * cosAlpha - v) / ((v * s + u * t) * sinAlpha), -1.0f, 1.0f);
    const Vector3f cPrime = q * a + safeSqrt(1.0f - q * q) * perpendicularPart(c, a);

    // Step 2: a point on the arc from b to c′, with cos θ to b uniform between 1 and b·c′.
    const float z = 1.0f - sample.y() * (1.0f - cPrime.dot(b));
    const Vector3f w = z * b + safeSqrt(1.0f - z * z) * perpendicularPart(cPrime, b);
    if (!w.allFinite())
        return std::nullopt;
    return w;
}

std::optional<Point2f> invertSphericalTriangleSample(const SphericalTriangle &triangle,
                                                     const Vector3f &w) {
    const Vector3f &a = triangle.a, &b = triangle.b, &c = triangle.c;
    if (!(triangle.solidAngle > 0.0f))
        return std::nullopt;
    // c′ lies on both great circles: the one through b and w (normal b × w) and the one
    // through a and c (normal c × a); of the two antipodal candidates, the one between a
    // and c.
    Vector3f cPrime = b.cross(w).cross(c.cross(a));
    if (!(cPrime.squaredNorm() > 0.0f))
        return Point2f(0.5f, 0.0f); // w is b itself (or the triangle is degenerate)
    cPrime.normalize();
    if (cPrime.dot(a + c) < 0.0f)
        cPrime = -cPrime;
    // Within a tenth of a degree of a, the sub-triangle has no area to measure.
    const float u = a.dot(cPrime) > 0.99999847691f
                        ? 0.0f
                        : SphericalTriangle(a, b, cPrime).solidAngle / triangle.solidAngle;
    const float denominator = 1.0f - cPrime.dot(b);
    const float v = denominator > 0.0f ? (1.0f - w.dot(b)) / denominator : 0.0f;
    return Point2f(std::clamp(u, 0.0f, 1.0f), std::clamp(v, 0.0f, 1.0f));
}

std::array<float, 4> cosineCornerWeights(const SphericalTriangle &triangle, const Vector3f &n) {
    constexpr float kFloor = 0.01f;
    const float cosA = std::max(kFloor, std::abs(n.dot(triangle.a)));
    const float cosB = std::max(kFloor, std::abs(n.dot(triangle.b)));
    const float cosC = std::max(kFloor, std::abs(n.dot(triangle.c)));
    return {cosB, cosB, cosA, cosC};
}

std::optional<Point2f> barycentricsAlong(const Point3f &p0, const Point3f &p1, const Point3f &p2,
                                         const Point3f &ref, const Vector3f &w) {
    const Vector3f e1 = p1 - p0, e2 = p2 - p0;
    const Vector3f s1 = w.cross(e2);
    const float divisor = s1.dot(e1);
    if (!(divisor != 0.0f))
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
