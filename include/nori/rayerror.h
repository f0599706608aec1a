// Floating-point error bounds for robust ray tracing (PBR 4th ed. §6.8): the γ_n
// bound of n roundings, and offsetting a ray origin past a hit point's error box.
#pragma once

#include <nori/vector.h>

namespace nori {

/// Bound on the relative error of n successive float roundings, n·ε/(1 − n·ε), with
/// ε = 2⁻²⁴ (PBR 4th ed. eq. 6.29).
constexpr float gammaBound(int n) {
    constexpr float kMachineEpsilon = 0.5f * std::numeric_limits<float>::epsilon();
    return (static_cast<float>(n) * kMachineEpsilon) /
           (1.0f - static_cast<float>(n) * kMachineEpsilon);
}

/// Moves p, known to lie within ±pError of the true surface point, along the normal n
/// to the side of w, just far enough that a ray leaving in direction w cannot hit the
/// surface again (PBR 4th ed. §6.8.6).
inline Point3f offsetRayOrigin(const Point3f &p, const Vector3f &pError, const Vector3f &n,
                               const Vector3f &w) {
    const float distance = n.cwiseAbs().dot(pError);
    Vector3f offset = distance * n;
    if (w.dot(n) < 0.0f)
        offset = -offset;
    Point3f po = p + offset;
    // Round away from p, so the offset survives the addition's own rounding.
    for (int i = 0; i < 3; ++i) {
        if (offset[i] > 0.0f)
            po[i] = std::nextafter(po[i], kInfinity);
        else if (offset[i] < 0.0f)
            po[i] = std::nextafter(po[i], -kInfinity);
    }
    return po;
}

} // namespace nori
