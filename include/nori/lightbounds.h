// Bounds of lights for choosing among many (Estevez and Kulla 2018, "Importance sampling
// of many lights with adaptive tree splitting"; PBR 4th ed. §6.8.3 and §12.6.3): a cone
// that holds a set of directions, and what a set of lights can send toward a point.
#pragma once

#include <nori/bbox.h>

namespace nori {

/// Every direction within angle θ of the unit axis w, kept as cos θ (PBR 4th ed. §6.8.3).
struct DirectionCone {
    Vector3f w = Vector3f(0.0f, 0.0f, 1.0f);
    float cosTheta = kInfinity; ///< above 1: the empty cone

    DirectionCone() = default;
    DirectionCone(const Vector3f &w, float cosTheta) : w(w.normalized()), cosTheta(cosTheta) {}
    /// The cone of the single direction w.
    explicit DirectionCone(const Vector3f &w) : DirectionCone(w, 1.0f) {}
    static DirectionCone entireSphere() { return {Vector3f(0.0f, 0.0f, 1.0f), -1.0f}; }

    bool isEmpty() const { return cosTheta > 1.0f; }
    /// Whether the unit vector v lies in the cone.
    bool contains(const Vector3f &v) const { return !isEmpty() && w.dot(v) >= cosTheta; }
};

/// The smallest cone (of this construction) that holds both cones.
DirectionCone coneUnion(const DirectionCone &a, const DirectionCone &b);

/// What one light, or a cluster of them, can send toward a point (PBR 4th ed. §12.6.3):
/// its points lie in `bounds`, its surface normals (the axes of emission) in the cone
/// (w, θo), and it emits up to θe away from a normal (π/2 for a Lambertian surface, π for
/// a point light). `phi` is π times the largest radiant intensity it sends (W/sr), so that
/// phi/d² is π times the irradiance it can cause at distance d: for a Lambertian surface
/// light (πLA), its power; for a point or spot light, π·I, not its power (4π·I), which
/// would favour point lights over surfaces of the same intensity fourfold. A two-sided
/// light emits about −normal too.
struct LightBounds {
    BoundingBox3f bounds;
    Vector3f w = Vector3f(0.0f, 0.0f, 1.0f);
    float phi = 0.0f;
    float cosThetaO = 1.0f;
    float cosThetaE = 0.0f;
    bool twoSided = false;

    /// The cost of a cluster for building the tree (PBR 4th ed. §12.6.3, after Estevez
    /// and Kulla's eq. 2): power times the solid angle its emission can reach.
    float orientationMeasure() const;
};

/// The bounds of both (a node of the light tree over two children).
LightBounds lightBoundsUnion(const LightBounds &a, const LightBounds &b);

/// LightBounds as the light tree evaluates them at every step down: the box replaced by
/// its bounding sphere, the sines precomputed.
struct LightImportance {
    Point3f center = Point3f(0.0f, 0.0f, 0.0f);
    float radius = 0.0f;
    Vector3f w = Vector3f(0.0f, 0.0f, 1.0f);
    float phi = 0.0f;
    float cosThetaO = 1.0f, sinThetaO = 0.0f, cosThetaE = 0.0f;
    bool twoSided = false;

    LightImportance() = default;
    explicit LightImportance(const LightBounds &bounds);

    /// An upper estimate of the light arriving at `p` (PBR 4th ed. §12.6.3): phi over the
    /// squared distance, times the cosine of the smallest angle any of its points could
    /// emit toward p at, and, when `n` is not zero, of the smallest angle of incidence on
    /// a surface of normal n there. Zero only when no point of the bounds can light p.
    float operator()(const Point3f &p, const Normal3f &n) const;
};

// The light tree's walk evaluates the importance of two nodes at every level, twice per
// light sample with MIS: inline, so that the walk's loop keeps its values in registers.

namespace detail {

/// cos(max(0, a − b)) from the sines and cosines of a and b, both in [0, π].
inline float cosSubClamped(float sinA, float cosA, float sinB, float cosB) {
    return cosA > cosB ? 1.0f : cosA * cosB + sinA * sinB;
}

/// sin(max(0, a − b)) likewise.
inline float sinSubClamped(float sinA, float cosA, float sinB, float cosB) {
    return cosA > cosB ? 0.0f : sinA * cosB - cosA * sinB;
}

} // namespace detail

inline float LightImportance::operator()(const Point3f &p, const Normal3f &n) const {
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
            cosThetaX = detail::cosSubClamped(sinThetaW, cosThetaW, sinThetaO, cosThetaO);
            sinThetaX = detail::sinSubClamped(sinThetaW, cosThetaW, sinThetaO, cosThetaO);
        }
        cosThetaP = detail::cosSubClamped(sinThetaX, cosThetaX, sinThetaB, cosThetaB);
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
            result *= detail::cosSubClamped(sinThetaI, cosThetaI, sinThetaB, cosThetaB);
        }
    }
    return std::max(result, 0.0f);
}

} // namespace nori
