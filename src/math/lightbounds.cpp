#include <nori/lightbounds.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace nori {

namespace {

float safeAcos(float x) {
    return std::acos(std::clamp(x, -1.0f, 1.0f));
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
