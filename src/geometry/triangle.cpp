// The double-precision re-test of a triangle hit too close to the ray's origin for the
// float test's t > 0 bound (PBR 4th ed. §6.8.7) to vouch for it.
#include <nori/triangle.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace nori {

namespace {

/// γ_n in double: n·ε/(1 − n·ε) with ε = 2⁻⁵³ (PBR 4th ed. eq. 6.29).
constexpr double gammaBoundDouble(int n) {
    constexpr double kMachineEpsilon = 0.5 * std::numeric_limits<double>::epsilon();
    return (n * kMachineEpsilon) / (1.0 - n * kMachineEpsilon);
}

} // namespace

bool triangleDistanceInDouble(const WatertightRay &ray, const Point3f &p0, const Point3f &p1,
                              const Point3f &p2, float &t) {
    // The float test's steps, each in double: vertices relative to the origin, sheared
    // into ray space by the ray's (float) shear, edge functions, scaled t. The shear
    // defines the ray here as it does in the float test.
    const Point3f *vertices[3] = {&p0, &p1, &p2};
    double x[3], y[3], z[3];
    for (int i = 0; i < 3; ++i) {
        const Point3f &p = *vertices[i];
        z[i] = static_cast<double>(p[ray.kz]) - ray.o[ray.kz];
        x[i] = static_cast<double>(p[ray.kx]) - ray.o[ray.kx] + static_cast<double>(ray.sx) * z[i];
        y[i] = static_cast<double>(p[ray.ky]) - ray.o[ray.ky] + static_cast<double>(ray.sy) * z[i];
    }
    const double e0 = x[1] * y[2] - y[1] * x[2];
    const double e1 = x[2] * y[0] - y[2] * x[0];
    const double e2 = x[0] * y[1] - y[0] * x[1];
    const double det = e0 + e1 + e2;
    if (det == 0.0 || !std::isfinite(det))
        return false;
    double sz[3];
    for (int i = 0; i < 3; ++i)
        sz[i] = static_cast<double>(ray.sz) * z[i];
    const double tHit = (e0 * sz[0] + e1 * sz[1] + e2 * sz[2]) / det;

    // The same bound as the float test's, with double's γ.
    const double maxZt = std::max({std::abs(sz[0]), std::abs(sz[1]), std::abs(sz[2])});
    const double maxXt = std::max({std::abs(x[0]), std::abs(x[1]), std::abs(x[2])});
    const double maxYt = std::max({std::abs(y[0]), std::abs(y[1]), std::abs(y[2])});
    const double deltaZ = gammaBoundDouble(3) * maxZt;
    const double deltaX = gammaBoundDouble(5) * (maxXt + maxZt);
    const double deltaY = gammaBoundDouble(5) * (maxYt + maxZt);
    const double deltaE =
        2.0 * (gammaBoundDouble(2) * maxXt * maxYt + deltaY * maxXt + deltaX * maxYt);
    const double maxE = std::max({std::abs(e0), std::abs(e1), std::abs(e2)});
    const double deltaT =
        3.0 * (gammaBoundDouble(3) * maxE * maxZt + deltaE * maxZt + deltaZ * maxE) / std::abs(det);
    const float tFloat = static_cast<float>(tHit);
    if (tHit <= deltaT || tFloat <= 0.0f)
        return false;
    t = tFloat;
    return true;
}

} // namespace nori
