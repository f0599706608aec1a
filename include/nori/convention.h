// The conventions in which the Nori course lineages differ, chosen per scene object by
// its `convention` parameter, or for a whole scene by `nori --convention`.
#pragma once

#include <nori/proplist.h>

namespace nori {

/// EPFL: Nori 2's (and Mitsuba's) choices, the default. ETH: those of ETH Zürich's
/// Computer Graphics course (2023–2024):
/// - cameras: EPFL mirrors the image's x (camera-space +x is the image's left), ETH
///   does not;
/// - the sphere's uv: EPFL u = ½ + φ/2π in [0, 1], ETH u = φ/2π in [−½, ½], with
///   φ = atan2(y, x); both v = 1 − θ/π, θ from +z.
enum class CourseConvention { EPFL, ETH };

/// Reads the `convention` parameter ("epfl", the default, or "eth"); throws
/// NoriException naming the value otherwise.
CourseConvention readCourseConvention(const PropertyList &props);

/// "epfl" or "eth".
const char *courseConventionName(CourseConvention convention);

} // namespace nori
