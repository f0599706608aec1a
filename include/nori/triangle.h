// The watertight ray–triangle test of Woop, Benthin and Wald ("Watertight Ray/Triangle
// Intersection", JCGT 2(1), 2013), with PBR 4th ed. §6.5.3's conservative t > 0 bound.
// Rays that hit an edge or vertex shared by two triangles hit at least one of them.
// A hit within the float bound of t = 0 is re-tested in double, where the bound is 2²⁹
// times smaller: the bound grows with the triangle's size, and a ray spawned 0.1 from a
// 10⁴-unit triangle would otherwise miss it (and a path leave the medium it bounds).
#pragma once

#include <nori/ray.h>
#include <nori/rayerror.h>

namespace nori {

/// What the test needs of a ray, computed once per ray: the axis permutation that
/// makes z the dominant direction and the shear that maps the ray onto +z.
struct WatertightRay {
    Point3f o;
    int kx, ky, kz;
    float sx, sy, sz;
    float mint, maxt;

    explicit WatertightRay(const Ray3f &ray) : o(ray.o), mint(ray.mint), maxt(ray.maxt) {
        const Vector3f absD = ray.d.cwiseAbs();
        kz = absD.x() > absD.y() ? (absD.x() > absD.z() ? 0 : 2) : (absD.y() > absD.z() ? 1 : 2);
        kx = kz == 2 ? 0 : kz + 1;
        ky = kx == 2 ? 0 : kx + 1;
        sx = -ray.d[kx] / ray.d[kz];
        sy = -ray.d[ky] / ray.d[kz];
        sz = 1.0f / ray.d[kz];
    }
};

/// For a hit whose float t is positive but within its error bound of 0: t recomputed in
/// double with the same bound in double (PBR 4th ed. §6.8.7 with ε = 2⁻⁵³). Returns true
/// and sets t if t is provably positive, false if it is not (the ray starts on or behind
/// the triangle's plane as far as any precision can tell). Out of line: rarely taken.
bool triangleDistanceInDouble(const WatertightRay &ray, const Point3f &p0, const Point3f &p1,
                              const Point3f &p2, float &t);

/// Intersects the ray with triangle (p0, p1, p2) within [mint, maxt]. On a hit, sets
/// t and the barycentrics (b1, b2) of p1 and p2 and returns true.
[[gnu::always_inline]] inline bool intersectTriangle(const WatertightRay &ray, const Point3f &p0,
                                                     const Point3f &p1, const Point3f &p2, float &t,
                                                     float &b1, float &b2) {
    // Vertices relative to the ray origin, permuted and sheared into ray space.
    const Vector3f a = p0 - ray.o, b = p1 - ray.o, c = p2 - ray.o;
    const float az = a[ray.kz], bz = b[ray.kz], cz = c[ray.kz];
    const float ax = a[ray.kx] + ray.sx * az, ay = a[ray.ky] + ray.sy * az;
    const float bx = b[ray.kx] + ray.sx * bz, by = b[ray.ky] + ray.sy * bz;
    const float cx = c[ray.kx] + ray.sx * cz, cy = c[ray.ky] + ray.sy * cz;

    // Edge functions: signed areas seen from the ray. A zero is re-evaluated in double
    // so that edges shared by two triangles are decided consistently.
    float e0 = bx * cy - by * cx;
    float e1 = cx * ay - cy * ax;
    float e2 = ax * by - ay * bx;
    if (e0 == 0.0f || e1 == 0.0f || e2 == 0.0f) {
        e0 = static_cast<float>(static_cast<double>(bx) * cy - static_cast<double>(by) * cx);
        e1 = static_cast<float>(static_cast<double>(cx) * ay - static_cast<double>(cy) * ax);
        e2 = static_cast<float>(static_cast<double>(ax) * by - static_cast<double>(ay) * bx);
    }
    if ((e0 < 0.0f || e1 < 0.0f || e2 < 0.0f) && (e0 > 0.0f || e1 > 0.0f || e2 > 0.0f))
        return false;
    const float det = e0 + e1 + e2;
    if (det == 0.0f || !std::isfinite(det))
        return false;

    // t scaled by det, compared without a division first.
    const float sAz = ray.sz * az, sBz = ray.sz * bz, sCz = ray.sz * cz;
    const float tScaled = e0 * sAz + e1 * sBz + e2 * sCz;
    if (det < 0.0f && (tScaled >= 0.0f || tScaled < ray.maxt * det))
        return false;
    if (det > 0.0f && (tScaled <= 0.0f || tScaled > ray.maxt * det))
        return false;

    const float invDet = 1.0f / det;
    float tHit = tScaled * invDet;

    // Reject hits whose t is not provably positive (PBR 4th ed. §6.8.7).
    const float maxZt = std::max({std::abs(sAz), std::abs(sBz), std::abs(sCz)});
    const float maxXt = std::max({std::abs(ax), std::abs(bx), std::abs(cx)});
    const float maxYt = std::max({std::abs(ay), std::abs(by), std::abs(cy)});
    const float deltaZ = gammaBound(3) * maxZt;
    const float deltaX = gammaBound(5) * (maxXt + maxZt);
    const float deltaY = gammaBound(5) * (maxYt + maxZt);
    const float deltaE = 2.0f * (gammaBound(2) * maxXt * maxYt + deltaY * maxXt + deltaX * maxYt);
    const float maxE = std::max({std::abs(e0), std::abs(e1), std::abs(e2)});
    const float deltaT =
        3.0f * (gammaBound(3) * maxE * maxZt + deltaE * maxZt + deltaZ * maxE) * std::abs(invDet);
    if (tHit <= deltaT && !triangleDistanceInDouble(ray, p0, p1, p2, tHit))
        return false;
    if (tHit < ray.mint || tHit > ray.maxt)
        return false;

    t = tHit;
    b1 = e1 * invDet;
    b2 = e2 * invDet;
    return true;
}

} // namespace nori
