// Ray differentials from the camera to every texture lookup (Igehy 1999, "Tracing Ray
// Differentials"; pbrt-v3 §10.1): the camera makes the rays through the neighbouring
// pixels, a hit turns them into its footprint (dp/dx, dp/dy and the uv derivatives),
// specular bounces carry them exactly, other bounces widen them as a ray cone.
#pragma once
#include <nori/ray.h>

namespace nori {

struct BSDFQueryRecord;
struct Intersection;

/// Fills its.dpdx, dpdy, dudx, dudy, dvdx, dvdy from the differentials of `ray` (zero
/// when it has none): the offset rays meet the hit's tangent plane at p + dp/dx and
/// p + dp/dy, and (du, dv) solve dp = dp/du·du + dp/dv·dv in the least-squares sense.
void computeDifferentials(Intersection &its, const Ray3f &ray);

/// Angular spread (radians) each non-specular bounce adds to a ray's differentials: the
/// footprint of later hits then grows by about this much per unit of distance, so
/// indirect texture lookups are filtered rather than aliased (a "ray cone", Akenine-Möller
/// et al. 2019; a conservative, scene-independent choice).
constexpr float kNonSpecularSpread = 0.1f;

/// The ray leaving `its` along the direction bRec.wo (local) that a BSDF sampled for the
/// incoming `ray`, with differentials: specular reflection and refraction (discrete
/// measure) carry them by Igehy's formulas; other lobes keep the footprint's origin
/// offsets and widen the directions by kNonSpecularSpread beyond the incoming spread.
Ray3f spawnScatteredRay(const Intersection &its, const Ray3f &ray, const BSDFQueryRecord &bRec);

} // namespace nori
