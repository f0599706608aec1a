#include <nori/sphericaltriangle.h>

#include <algorithm>
#include <cmath>

namespace nori {

namespace {

// The construction and its inverse run in double: on slivers (vertices 135° to 160° apart
// as seen) Arvo's q and the arcs' perpendiculars cancel catastrophically, and in float a
// sample inverted came back up to 0.024 off, the error set by the compiler's order of
// summation in the dot products (GCC 6.3e-3, clang 0.024, the same inputs). The inputs and
// the results stay float.

/// The unit vector along the part of v perpendicular to the unit vector w.
Vector3d perpendicularPart(const Vector3d &v, const Vector3d &w) {
    return (v - v.dot(w) * w).normalized();
}

/// Van Oosterom and Strackee's solid angle of the unit vectors a, b, c (0 when not finite).
double solidAngleOf(const Vector3d &a, const Vector3d &b, const Vector3d &c) {
    const double omega =
        2.0 * std::atan2(std::abs(a.dot(b.cross(c))), 1.0 + a.dot(b) + b.dot(c) + c.dot(a));
    return std::isfinite(omega) ? std::abs(omega) : 0.0;
}

Vector3d toDouble(const Vector3f &v) {
    return v.cast<double>();
}

} // namespace

SphericalTriangle::SphericalTriangle(const Vector3f &a, const Vector3f &b, const Vector3f &c)
    : a(a), b(b), c(c),
      solidAngle(static_cast<float>(solidAngleOf(toDouble(a), toDouble(b), toDouble(c)))) {}

float sphericalTriangleSolidAngle(const Point3f &p0, const Point3f &p1, const Point3f &p2,
                                  const Point3f &ref) {
    return SphericalTriangle((p0 - ref).normalized(), (p1 - ref).normalized(),
                             (p2 - ref).normalized())
        .solidAngle;
}

std::optional<Vector3f> sampleSphericalTriangle(const SphericalTriangle &triangle,
                                                const Point2f &sample) {
    const Vector3d a = toDouble(triangle.a), b = toDouble(triangle.b), c = toDouble(triangle.c);
    // The angle α at a is the angle between the arcs' tangents there, which a × b and
    // a × c are, turned by 90° about a: cos α from their dot product, sin α from their
    // cross product, (a × b) × (a × c) = (a·(b × c))·a, over the same lengths.
    const Vector3d ab = a.cross(b), ac = a.cross(c);
    const double lengths = ab.norm() * ac.norm();
    if (!(lengths > 0.0) || !(triangle.solidAngle > 0.0f))
        return std::nullopt;
    const double cosAlpha = std::clamp(ab.dot(ac) / lengths, -1.0, 1.0);
    const double sinAlpha = std::min(std::abs(a.dot(b.cross(c))) / lengths, 1.0);

    // Arvo's step 1: the sub-triangle (a, b, c′) of area Â = u·Ω has its vertex c′ on the
    // arc from a to c at cos(arc a c′) = q, with s, t = sin, cos (Â − α) and cos(arc a b).
    const double areaSub = double(sample.x()) * double(triangle.solidAngle);
    const double sinArea = std::sin(areaSub), cosArea = std::cos(areaSub);
    const double s = sinArea * cosAlpha - cosArea * sinAlpha;
    const double t = cosArea * cosAlpha + sinArea * sinAlpha;
    const double u = t - cosAlpha, v = s + sinAlpha * a.dot(b);
    const double q =
        std::clamp(((v * t - u * s) * cosAlpha - v) / ((v * s + u * t) * sinAlpha), -1.0, 1.0);
    const Vector3d cPrime = q * a + std::sqrt(std::max(0.0, 1.0 - q * q)) * perpendicularPart(c, a);

    // Step 2: a point on the arc from b to c′, with cos θ to b uniform between 1 and b·c′.
    const double z = 1.0 - double(sample.y()) * (1.0 - cPrime.dot(b));
    const Vector3d w = z * b + std::sqrt(std::max(0.0, 1.0 - z * z)) * perpendicularPart(cPrime, b);
    if (!w.allFinite())
        return std::nullopt;
    return Vector3f(w.cast<float>());
}

std::optional<Point2f> invertSphericalTriangleSample(const SphericalTriangle &triangle,
                                                     const Vector3f &w) {
    if (!(triangle.solidAngle > 0.0f))
        return std::nullopt;
    const Vector3d a = toDouble(triangle.a), b = toDouble(triangle.b), c = toDouble(triangle.c);
    const Vector3d direction = toDouble(w);
    // c′ lies on both great circles: the one through b and w (normal b × w) and the one
    // through a and c (normal c × a); of the two antipodal candidates, the one between a
    // and c.
    Vector3d cPrime = b.cross(direction).cross(c.cross(a));
    if (!(cPrime.squaredNorm() > 0.0))
        return Point2f(0.5f, 0.0f); // w is b itself (or the triangle is degenerate)
    cPrime.normalize();
    if (cPrime.dot(a + c) < 0.0)
        cPrime = -cPrime;
    // Within a tenth of a degree of a, the sub-triangle has no area to measure.
    const double u =
        a.dot(cPrime) > 0.99999847691 ? 0.0 : solidAngleOf(a, b, cPrime) / solidAngleOf(a, b, c);
    const double denominator = 1.0 - cPrime.dot(b);
    const double v = denominator > 0.0 ? (1.0 - direction.dot(b)) / denominator : 0.0;
    return Point2f(static_cast<float>(std::clamp(u, 0.0, 1.0)),
                   static_cast<float>(std::clamp(v, 0.0, 1.0)));
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
