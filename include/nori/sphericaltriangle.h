// Spherical triangles: the solid angle a triangle subtends at a point, and directions
// sampled uniformly within it (Arvo 1995, "Stratified sampling of spherical triangles";
// PBR 4th ed. §6.5.4).
#pragma once

#include <nori/vector.h>

#include <array>
#include <optional>

namespace nori {

/// Below this solid angle (steradians), the sampling's spherical trigonometry loses its
/// precision in float, and area sampling is as good: the triangle is nearly a point.
/// Above the maximum, the triangle nearly covers a hemisphere, where the construction is
/// ill-conditioned. Both are pbrt-v4's bounds (PBR 4th ed. §6.5.4).
inline constexpr float kMinSphericalTriangleSolidAngle = 3e-4f;
inline constexpr float kMaxSphericalTriangleSolidAngle = 6.22f;

/// A triangle as seen from a point: the unit vectors a, b, c toward its vertices and the
/// solid angle Ω they enclose, in [0, 2π): Van Oosterom and Strackee 1983,
/// Ω = 2·atan2(|a·(b × c)|, 1 + a·b + b·c + c·a). Zero when the point lies in the
/// triangle's plane.
struct SphericalTriangle {
    Vector3f a, b, c;
    float solidAngle = 0.0f;

    SphericalTriangle() = default;
    SphericalTriangle(const Vector3f &a, const Vector3f &b, const Vector3f &c);
};

/// The solid angle of triangle (p0, p1, p2) seen from `ref`.
float sphericalTriangleSolidAngle(const Point3f &p0, const Point3f &p1, const Point3f &p2,
                                  const Point3f &ref);

/// A direction uniform in the solid angle of `triangle` (density 1/Ω), by Arvo's
/// construction: sample.x() chooses the area u·Ω of a sub-triangle (a, b, c′) with c′ on
/// the arc from a to c, sample.y() a point on the arc from b to c′ whose cos θ to b is
/// uniform. Nothing when the triangle is degenerate as seen (Ω = 0, a vertex at the point).
std::optional<Vector3f> sampleSphericalTriangle(const SphericalTriangle &triangle,
                                                const Point2f &sample);

/// The sample that sampleSphericalTriangle maps to the unit direction w inside `triangle`
/// (PBR 4th ed. §6.5.4, InvertSphericalTriangleSample): c′ where the great circle
/// through b and w meets the arc from a to c, then u = Ω(a, b, c′)/Ω and
/// v = (1 − w·b)/(1 − c′·b), each clamped to [0, 1]. Nothing for a degenerate triangle.
std::optional<Point2f> invertSphericalTriangleSample(const SphericalTriangle &triangle,
                                                     const Vector3f &w);

/// The weights of squareToBilinear at the corners of sampleSphericalTriangle's square,
/// which it maps to b, b, a and c (u = 0 is the arc from b to a, v = 0 the vertex b): the
/// cosines of a, b, c to the normal n, not below 0.01, so that warping the sample by them
/// draws directions roughly in proportion to cos θ at a shading point (PBR 4th ed.
/// §6.5.4; pbrt-v4 takes |cos θ|, for light through the surface too).
std::array<float, 4> cosineCornerWeights(const SphericalTriangle &triangle, const Vector3f &n);

/// Where the ray from `ref` along the unit direction w meets the plane of triangle (p0,
/// p1, p2) (Möller and Trumbore 1997): the barycentrics (b1, b2) of p1 and p2, clamped
/// into the triangle (a direction sampled inside it can leave it by rounding). Nothing
/// when w is parallel to the plane.
std::optional<Point2f> barycentricsAlong(const Point3f &p0, const Point3f &p1, const Point3f &p2,
                                         const Point3f &ref, const Vector3f &w);

} // namespace nori
