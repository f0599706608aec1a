#include <nori/lightbounds.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace nori {

namespace {

float safeAcos(float x) {
    return std::acos(std::clamp(x, -1.0f, 1.0f));
}

/// cos(max(0, a − b)) from the sines and cosines of a and b, both in [0, π].
float cosSubClamped(float sinA, float cosA, float sinB, float cosB) {
    return cosA > cosB ? 1.0f : cosA * cosB + sinA * sinB;
}

/// sin(max(0, a − b)) likewise.
float sinSubClamped(float sinA, float cosA, float sinB, float cosB) {
    return cosA > cosB ? 0.0f : sinA * cosB - cosA * sinB;
}

} // namespace

DirectionCone coneUnion(const DirectionCone &a, const DirectionCone &b) {
    if (a.isEmpty())
        return b;
    if (b.isEmpty())
        return a;
    // One cone inside the other.
    const float thetaA = safeAcos(a.cosTheta), thetaB = safeAcos(b.cosTheta);
    const float thetaD = safeAcos(a.w.dot(b.w));
    if (std::min(thetaD + thetaB, kPi) <= thetaA)
        return a;
    if (std::min(thetaD + thetaA, kPi) <= thetaB)
        return b;
    // The merged cone spans both: its half-angle is half the arc from a's far edge to
    // b's, and its axis is a's turned toward b by the difference.
    const float thetaO = 0.5f * (thetaA + thetaD + thetaB);
    if (thetaO >= kPi)
        return DirectionCone::entireSphere();
    const Vector3f axis = a.w.cross(b.w);
    if (axis.squaredNorm() == 0.0f)
        return DirectionCone::entireSphere();
    const Vector3f w = Eigen::AngleAxisf(thetaO - thetaA, axis.normalized()) * a.w;
    return {w, std::cos(thetaO)};
}

LightBounds lightBoundsUnion(const LightBounds &a, const LightBounds &b) {
    if (a.phi == 0.0f)
        return b;
    if (b.phi == 0.0f)
        return a;
    const DirectionCone cone =
        coneUnion(DirectionCone(a.w, a.cosThetaO), DirectionCone(b.w, b.cosThetaO));
    LightBounds result;
    result.bounds = a.bounds;
    result.bounds.expandBy(b.bounds);
    result.w = cone.w;
    result.phi = a.phi + b.phi;
    result.cosThetaO = cone.cosTheta;
    result.cosThetaE = std::min(a.cosThetaE, b.cosThetaE);
    result.twoSided = a.twoSided || b.twoSided;
    return result;
}

LightImportance::LightImportance(const LightBounds &bounds)
    : center(bounds.bounds.getCenter()), radius(0.5f * bounds.bounds.getExtents().norm()),
      w(bounds.w), phi(bounds.phi), cosThetaO(bounds.cosThetaO),
      sinThetaO(safeSqrt(1.0f - bounds.cosThetaO * bounds.cosThetaO)), cosThetaE(bounds.cosThetaE),
      twoSided(bounds.twoSided) {}

float LightImportance::operator()(const Point3f &p, const Normal3f &n) const {
    const Vector3f fromCenter = p - center;
    const float distanceSquared = fromCenter.squaredNorm();
    const float distance = std::sqrt(distanceSquared);
    const float invDistance = distance > 0.0f ? 1.0f / distance : 0.0f;
    const Vector3f wi = distance > 0.0f ? Vector3f(fromCenter * invDistance) : w;
    // θb: the half-angle the bounding sphere subtends at p (π from inside it).
    float sinThetaB = 0.0f, cosThetaB = -1.0f;
    if (distance > radius) {
        sinThetaB = radius * invDistance;
        cosThetaB = safeSqrt(1.0f - sinThetaB * sinThetaB);
    }
    // θ' = max(0, θw − θo − θb), with θw the angle between the axis w and the direction
    // from the centre to p: the smallest angle between a normal and a direction from a
    // point of the bounds to p. Beyond θe, nothing reaches p. (Each clamped difference
    // is 0 when its first angle is the smaller, which spares the square roots of the
    // lights that emit every way.)
    float cosThetaP = 1.0f;
    if (cosThetaO > -1.0f) {
        float cosThetaW = w.dot(wi);
        if (twoSided)
            cosThetaW = std::abs(cosThetaW);
        float cosThetaX = 1.0f, sinThetaX = 0.0f;
        if (cosThetaW <= cosThetaO) {
            const float sinThetaW = safeSqrt(1.0f - cosThetaW * cosThetaW);
            cosThetaX = cosSubClamped(sinThetaW, cosThetaW, sinThetaO, cosThetaO);
            sinThetaX = sinSubClamped(sinThetaW, cosThetaW, sinThetaO, cosThetaO);
        }
        cosThetaP = cosSubClamped(sinThetaX, cosThetaX, sinThetaB, cosThetaB);
    }
    if (cosThetaP <= cosThetaE)
        return 0.0f;
    // The squared distance, kept from vanishing at points in or near the bounds (pbrt-v4
    // clamps it to half the box's diagonal, the sphere's radius).
    float result = phi * cosThetaP / std::max(distanceSquared, radius);
    // At a surface, the smallest angle of incidence max(0, θi − θb) (either side, for
    // transmission).
    if (n != Normal3f(0.0f, 0.0f, 0.0f)) {
        const float cosThetaI = std::abs(wi.dot(n));
        if (cosThetaI <= cosThetaB) {
            const float sinThetaI = safeSqrt(1.0f - cosThetaI * cosThetaI);
            result *= cosSubClamped(sinThetaI, cosThetaI, sinThetaB, cosThetaB);
        }
    }
    return std::max(result, 0.0f);
}

float LightBounds::orientationMeasure() const {
    // ∫ over the directions within θo + θe of w of the emission's falloff (PBR 4th ed.
    // §12.6.3, EvaluateCost): the solid angle of the cone of normals, plus the band
    // beyond it weighted by cos(θ − θo).
    const float thetaO = safeAcos(cosThetaO), thetaE = safeAcos(cosThetaE);
    const float thetaW = std::min(thetaO + thetaE, kPi);
    const float sinThetaO = safeSqrt(1.0f - cosThetaO * cosThetaO);
    return 2.0f * kPi * (1.0f - cosThetaO) +
           0.5f * kPi *
               (2.0f * thetaW * sinThetaO - std::cos(thetaO - 2.0f * thetaW) -
                2.0f * thetaO * sinThetaO + cosThetaO);
}

} // namespace nori
