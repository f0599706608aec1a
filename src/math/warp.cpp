#include <nori/warp.h>

#include <limits>

// Weak definitions: a course's warp.cpp among the plugins defines the same functions
// strongly, and the linker takes those (see warp.h).
#define NORI_REPLACEABLE __attribute__((weak))

namespace nori {

namespace {

/// Whether v is (up to round-off) a unit vector; densities are 0 off the sphere.
bool isUnit(const Vector3f &v) {
    return std::abs(v.squaredNorm() - 1.0f) < 1e-3f;
}

/// The unit direction at polar angle θ (given as tan²θ, up to +∞) and azimuth φ, as
/// (tan θ cos φ, tan θ sin φ, 1)/√(1 + tan²θ): near the pole, where the lobes of smooth
/// microfacets live, cos θ = 1/√(1 + tan²θ) rounds to 1 in float, and sin θ recovered
/// from it (√(1 − cos²θ)) loses every digit (α = 0.0025: a direction in 40 drawn onto
/// the pole itself); tan θ keeps them.
Vector3f directionFromTan2(float tan2Theta, float phi) {
    if (std::isinf(tan2Theta))
        return Vector3f(std::cos(phi), std::sin(phi), 0.0f);
    const float tanTheta = std::sqrt(tan2Theta), cosTheta = 1.0f / std::sqrt(1.0f + tan2Theta);
    return Vector3f(tanTheta * cosTheta * std::cos(phi), tanTheta * cosTheta * std::sin(phi),
                    cosTheta);
}

/// tan²θ of a unit vector from its components, (x² + y²)/z², which keeps its digits near
/// the pole where (1 − z²)/z² cancels.
float tan2ThetaOf(const Vector3f &m) {
    return (m.x() * m.x() + m.y() * m.y()) / (m.z() * m.z());
}

/// Inverse of the 1D tent's CDF on [-1, 1].
float tent1D(float u) {
    return u < 0.5f ? std::sqrt(2.0f * u) - 1.0f : 1.0f - std::sqrt(2.0f - 2.0f * u);
}

/// x in [0, 1) with density proportional to (1 − x)·a + x·b (a, b ≥ 0, not both 0): the
/// root of the CDF's quadratic in its cancellation-free form (PBR 4th ed. §A.5.1).
float sampleLinear(float u, float a, float b) {
    if (u == 0.0f && a == 0.0f)
        return 0.0f;
    const float x = u * (a + b) / (a + std::sqrt(lerp(u, a * a, b * b)));
    return std::min(x, 1.0f - std::numeric_limits<float>::epsilon() / 2.0f);
}

} // namespace

NORI_REPLACEABLE Point2f Warp::squareToBilinear(const Point2f &sample,
                                                const std::array<float, 4> &w) {
    if (w[0] + w[1] + w[2] + w[3] == 0.0f)
        return sample;
    // The marginal in y is linear between the rows' sums; the conditional in x linear
    // between the weights interpolated at that y.
    const float y = sampleLinear(sample.y(), w[0] + w[1], w[2] + w[3]);
    const float x = sampleLinear(sample.x(), lerp(y, w[0], w[2]), lerp(y, w[1], w[3]));
    return Point2f(x, y);
}

NORI_REPLACEABLE float Warp::squareToBilinearPdf(const Point2f &p, const std::array<float, 4> &w) {
    if (!((p.array() >= 0.0f).all() && (p.array() <= 1.0f).all()))
        return 0.0f;
    const float total = w[0] + w[1] + w[2] + w[3];
    if (total == 0.0f)
        return 1.0f;
    const float x = p.x(), y = p.y();
    return 4.0f *
           ((1.0f - x) * (1.0f - y) * w[0] + x * (1.0f - y) * w[1] + (1.0f - x) * y * w[2] +
            x * y * w[3]) /
           total;
}

NORI_REPLACEABLE Vector3f Warp::sphericalDirection(float cosTheta, float phi) {
    const float sinTheta = safeSqrt(1.0f - cosTheta * cosTheta);
    return Vector3f(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta);
}

NORI_REPLACEABLE Point2f Warp::squareToUniformSquare(const Point2f &sample) {
    return sample;
}

NORI_REPLACEABLE float Warp::squareToUniformSquarePdf(const Point2f &p) {
    return (p.array() >= 0.0f).all() && (p.array() <= 1.0f).all() ? 1.0f : 0.0f;
}

NORI_REPLACEABLE Point2f Warp::squareToTent(const Point2f &sample) {
    return Point2f(tent1D(sample.x()), tent1D(sample.y()));
}

NORI_REPLACEABLE float Warp::squareToTentPdf(const Point2f &p) {
    return std::max(0.0f, 1.0f - std::abs(p.x())) * std::max(0.0f, 1.0f - std::abs(p.y()));
}

NORI_REPLACEABLE Point2f Warp::squareToUniformDisk(const Point2f &sample) {
    const float r = std::sqrt(sample.x()), phi = 2.0f * kPi * sample.y();
    return Point2f(r * std::cos(phi), r * std::sin(phi));
}

NORI_REPLACEABLE float Warp::squareToUniformDiskPdf(const Point2f &p) {
    return p.squaredNorm() <= 1.0f ? kInvPi : 0.0f;
}

NORI_REPLACEABLE Point2f Warp::squareToUniformDiskConcentric(const Point2f &sample) {
    // Shirley & Chiu 1997: map concentric squares to concentric circles.
    const Point2f offset(2.0f * sample.x() - 1.0f, 2.0f * sample.y() - 1.0f);
    if (offset.x() == 0.0f && offset.y() == 0.0f)
        return Point2f(0.0f, 0.0f);
    float r, theta;
    if (std::abs(offset.x()) > std::abs(offset.y())) {
        r = offset.x();
        theta = (kPi / 4.0f) * (offset.y() / offset.x());
    } else {
        r = offset.y();
        theta = (kPi / 2.0f) - (kPi / 4.0f) * (offset.x() / offset.y());
    }
    return Point2f(r * std::cos(theta), r * std::sin(theta));
}

NORI_REPLACEABLE float Warp::squareToUniformDiskConcentricPdf(const Point2f &p) {
    return squareToUniformDiskPdf(p);
}

NORI_REPLACEABLE Point2f Warp::squareToUniformTriangle(const Point2f &sample) {
    // Folding the square along its diagonal keeps the density uniform.
    return sample.x() + sample.y() <= 1.0f ? sample : Point2f(1.0f - sample.x(), 1.0f - sample.y());
}

NORI_REPLACEABLE float Warp::squareToUniformTrianglePdf(const Point2f &p) {
    return p.x() >= 0.0f && p.y() >= 0.0f && p.x() + p.y() <= 1.0f ? 2.0f : 0.0f;
}

NORI_REPLACEABLE Vector3f Warp::squareToUniformSphere(const Point2f &sample) {
    return sphericalDirection(1.0f - 2.0f * sample.x(), 2.0f * kPi * sample.y());
}

NORI_REPLACEABLE float Warp::squareToUniformSpherePdf(const Vector3f &v) {
    return isUnit(v) ? kInvFourPi : 0.0f;
}

Vector3f Warp::squareToEqualAreaSphere(const Point2f &sample) {
    // To [−1, 1]²; r is the distance from the square's rim along the diagonals (1 on the
    // inner diamond's edge, the equator), φ the angle within the quadrant.
    const float u = 2.0f * sample.x() - 1.0f, v = 2.0f * sample.y() - 1.0f;
    const float up = std::abs(u), vp = std::abs(v);
    const float signedDistance = 1.0f - (up + vp);
    const float r = 1.0f - std::abs(signedDistance);
    const float phi = (r == 0.0f ? 1.0f : (vp - up) / r + 1.0f) * kPi / 4.0f;
    // Equal area: the diamond of "radius" r holds the cap of height r², z = ±(1 − r²).
    const float z = std::copysign(1.0f - r * r, signedDistance);
    const float scale = r * std::sqrt(std::max(0.0f, 2.0f - r * r));
    return Vector3f(std::copysign(std::cos(phi), u) * scale,
                    std::copysign(std::sin(phi), v) * scale, z);
}

float Warp::squareToEqualAreaSpherePdf(const Vector3f &v) {
    return isUnit(v) ? kInvFourPi : 0.0f;
}

Point2f Warp::equalAreaSphereToSquare(const Vector3f &d) {
    // The forward map backwards: r = √(1 − |z|), and within the quadrant the angle φ of
    // (|x|, |y|) splits r into u' = r(1 − 2φ/π) and v' = r·2φ/π.
    const float x = std::abs(d.x()), y = std::abs(d.y()), z = std::abs(d.z());
    const float r = std::sqrt(std::max(0.0f, 1.0f - z));
    const float phi = std::atan2(y, x) * (2.0f / kPi); // in [0, 1]
    float v = phi * r, u = r - v;
    if (d.z() < 0.0f) {
        // The southern hemisphere lies in the corners: mirror across the diagonal.
        std::swap(u, v);
        u = 1.0f - u;
        v = 1.0f - v;
    }
    u = std::copysign(u, d.x());
    v = std::copysign(v, d.y());
    return Point2f(0.5f * (u + 1.0f), 0.5f * (v + 1.0f));
}

NORI_REPLACEABLE Vector3f Warp::squareToUniformHemisphere(const Point2f &sample) {
    return sphericalDirection(sample.x(), 2.0f * kPi * sample.y());
}

NORI_REPLACEABLE float Warp::squareToUniformHemispherePdf(const Vector3f &v) {
    return isUnit(v) && v.z() >= 0.0f ? kInvTwoPi : 0.0f;
}

NORI_REPLACEABLE Vector3f Warp::squareToCosineHemisphere(const Point2f &sample) {
    // Malley: a uniform point on the disk lifted to the hemisphere is cosine distributed.
    const Point2f d = squareToUniformDiskConcentric(sample);
    return Vector3f(d.x(), d.y(), safeSqrt(1.0f - d.squaredNorm()));
}

NORI_REPLACEABLE float Warp::squareToCosineHemispherePdf(const Vector3f &v) {
    return isUnit(v) && v.z() >= 0.0f ? v.z() * kInvPi : 0.0f;
}

NORI_REPLACEABLE Vector3f Warp::squareToCosinePowerHemisphere(const Point2f &sample,
                                                              float exponent) {
    // The CDF of cos θ is cos^{n+1} θ, so cos θ = u^{1/(n+1)}.
    return sphericalDirection(std::pow(sample.x(), 1.0f / (exponent + 1.0f)),
                              2.0f * kPi * sample.y());
}

NORI_REPLACEABLE float Warp::squareToCosinePowerHemispherePdf(const Vector3f &v, float exponent) {
    if (!isUnit(v) || v.z() < 0.0f)
        return 0.0f;
    return (exponent + 1.0f) * kInvTwoPi * std::pow(v.z(), exponent);
}

NORI_REPLACEABLE Vector3f Warp::squareToUniformSphereCap(const Point2f &sample, float cosThetaMax) {
    // cos θ is uniform on [cosThetaMax, 1] (a cap's area is linear in cos θ).
    return sphericalDirection(1.0f - sample.x() * (1.0f - cosThetaMax), 2.0f * kPi * sample.y());
}

NORI_REPLACEABLE float Warp::squareToUniformSphereCapPdf(const Vector3f &v, float cosThetaMax) {
    if (!isUnit(v) || v.z() < cosThetaMax)
        return 0.0f;
    return kInvTwoPi / (1.0f - cosThetaMax);
}

NORI_REPLACEABLE Vector3f Warp::squareToBeckmann(const Point2f &sample, float alpha) {
    // Inverting the CDF of tan²θ: tan²θ = −α² ln(1 − u).
    const float tan2Theta = -alpha * alpha * std::log1p(-sample.x());
    return directionFromTan2(tan2Theta, 2.0f * kPi * sample.y());
}

NORI_REPLACEABLE float Warp::squareToBeckmannPdf(const Vector3f &m, float alpha) {
    const float cos2Theta = m.z() * m.z();
    // Below cos²θ ~ 1e-20, D has underflowed to 0 (and the formula would give 0/0).
    if (!isUnit(m) || m.z() <= 0.0f || cos2Theta < 1e-20f)
        return 0.0f;
    const float tan2Theta = tan2ThetaOf(m);
    const float d =
        std::exp(-tan2Theta / (alpha * alpha)) / (kPi * alpha * alpha * cos2Theta * cos2Theta);
    return d * m.z();
}

NORI_REPLACEABLE Vector3f Warp::squareToGGX(const Point2f &sample, float alpha) {
    // Inverting the CDF of tan²θ: tan²θ = α² u/(1 − u).
    const float tan2Theta = alpha * alpha * sample.x() / (1.0f - sample.x());
    return directionFromTan2(tan2Theta, 2.0f * kPi * sample.y());
}

NORI_REPLACEABLE float Warp::squareToGGXPdf(const Vector3f &m, float alpha) {
    if (!isUnit(m) || m.z() <= 0.0f)
        return 0.0f;
    // D = α²/(π cos⁴θ (α² + tan²θ)²) = α²/(π (α² cos²θ + sin²θ)²), the second form
    // being finite at grazing angles, with sin²θ = x² + y² (not 1 − z², which cancels
    // near the pole).
    const float alpha2 = alpha * alpha;
    const float root = alpha2 * m.z() * m.z() + m.x() * m.x() + m.y() * m.y();
    const float d = alpha2 / (kPi * root * root);
    return d * m.z();
}

NORI_REPLACEABLE Vector3f Warp::squareToGTR1(const Point2f &sample, float alpha) {
    const float alpha2 = alpha * alpha, u = sample.x();
    // Burley 2012, B.2: cos²θ = (1 − α^{2(1−u)})/(1 − α²), so that
    // tan²θ = (α^{2(1−u)} − α²)/(1 − α^{2(1−u)}) = α²(α^{−2u} − 1)/(1 − α^{2(1−u)}),
    // written with expm1 to keep its digits near the pole; α → 1 is the cosine lobe,
    // tan²θ = u/(1 − u).
    const float logAlpha2 = std::log(alpha2);
    const float tan2Theta =
        std::abs(1.0f - alpha2) < 1e-4f
            ? u / (1.0f - u)
            : alpha2 * std::expm1(-u * logAlpha2) / -std::expm1((1.0f - u) * logAlpha2);
    return directionFromTan2(tan2Theta, 2.0f * kPi * sample.y());
}

NORI_REPLACEABLE float Warp::squareToGTR1Pdf(const Vector3f &m, float alpha) {
    if (!isUnit(m) || m.z() <= 0.0f)
        return 0.0f;
    const float alpha2 = alpha * alpha;
    const float d =
        std::abs(1.0f - alpha2) < 1e-4f
            ? kInvPi
            // 1 + (α² − 1) cos²θ = α² cos²θ + sin²θ, with sin²θ = x² + y².
            : (alpha2 - 1.0f) / (kPi * std::log(alpha2) *
                                 (alpha2 * m.z() * m.z() + m.x() * m.x() + m.y() * m.y()));
    return d * m.z();
}

NORI_REPLACEABLE Vector3f Warp::squareToHenyeyGreenstein(const Point2f &sample, float g) {
    float cosTheta;
    if (std::abs(g) < 1e-3f) {
        cosTheta = 1.0f - 2.0f * sample.x();
    } else {
        // Inverse CDF of HG in cos θ (PBR 3rd ed. eq. 15.7, for directions about +z).
        const float square = (1.0f - g * g) / (1.0f - g + 2.0f * g * sample.x());
        cosTheta = std::clamp((1.0f + g * g - square * square) / (2.0f * g), -1.0f, 1.0f);
    }
    return sphericalDirection(cosTheta, 2.0f * kPi * sample.y());
}

NORI_REPLACEABLE float Warp::squareToHenyeyGreensteinPdf(const Vector3f &v, float g) {
    if (!isUnit(v))
        return 0.0f;
    const float denominator = 1.0f + g * g - 2.0f * g * v.z();
    return kInvFourPi * (1.0f - g * g) / (denominator * std::sqrt(denominator));
}

} // namespace nori
