// Spherical triangles: the solid angle a triangle subtends at a point, and directions
// sampled uniformly within it (Arvo 1995, "Stratified sampling of spherical triangles";
// PBR 4th ed. §6.5.4), returned as barycentrics of the point they hit.
#pragma once

#include <nori/vector.h>

#include <optional>

namespace nori {

/// Below this solid angle (steradians), the sampling's spherical trigonometry loses its
/// precision in float, and area sampling is as good: the triangle is nearly a point.
/// Above the maximum, the triangle nearly covers a hemisphere, where the construction is
/// ill-conditioned. Both are pbrt-v4's bounds (PBR 4th ed. §6.5.4).
inline constexpr float kMinSphericalTriangleSolidAngle = 3e-4f;
inline constexpr float kMaxSphericalTriangleSolidAngle = 6.22f;

/// The solid angle of triangle (p0, p1, p2) seen from `ref`, in [0, 2π): Van Oosterom and
/// Strackee 1983, Ω = 2·atan2(|a·(b × c)|, 1 + a·b + b·c + c·a) for the unit vectors a,
/// b, c from ref to the vertices. Zero when ref lies in the triangle's plane.
float sphericalTriangleSolidAngle(const Point3f &p0, const Point3f &p1, const Point3f &p2,
                                  const Point3f &ref);

/// A direction from `ref` uniform in the solid angle of triangle (p0, p1, p2), by Arvo's
/// construction: sample.x() chooses the area of a sub-triangle (a, b, c′) with c′ on the
/// arc from a to c, sample.y() a point on the arc from b to c′ whose cos θ to b is
/// uniform. Returns the barycentrics (b1, b2) of vertices p1 and p2 of the point where
/// the direction meets the triangle, or nothing when the triangle is degenerate as seen
/// from ref (a vertex at ref, or ref in its plane). The density is 1/Ω with Ω from
/// sphericalTriangleSolidAngle, to float precision when Ω lies between the bounds above.
std::optional<Point2f> sampleSphericalTriangle(const Point3f &p0, const Point3f &p1,
                                               const Point3f &p2, const Point3f &ref,
                                               const Point2f &sample);

} // namespace nori
