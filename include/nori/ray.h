// A ray segment o + t·d, t in [mint, maxt], with the reciprocal direction cached.
#pragma once

#include <nori/vector.h>

namespace nori {

struct Ray3f {
    Point3f o;
    Vector3f d;
    Vector3f dRcp;
    float mint = kEpsilon;
    float maxt = kInfinity;

    /// Ray differentials (Igehy 1999; pbrt-v3 §2.5.1): the rays through the neighbouring
    /// pixels in x and y, carried through specular bounces. They size the texture
    /// footprint at a hit; shadow rays and test rays go without.
    bool hasDifferentials = false;
    Point3f rxOrigin, ryOrigin;
    Vector3f rxDirection, ryDirection;

    Ray3f() = default;
    Ray3f(const Point3f &o, const Vector3f &d, float mint = kEpsilon, float maxt = kInfinity)
        : o(o), d(d), mint(mint), maxt(maxt) {
        update();
    }

    /// Recomputes the cached reciprocal direction after d changes.
    /// The same ray with another segment (Nori 2).
    Ray3f(const Ray3f &ray, float mint, float maxt) : Ray3f(ray.o, ray.d, mint, maxt) {}
    void update() { dRcp = d.cwiseInverse(); }
    /// The ray pointing the other way, with the same segment.
    Ray3f reverse() const { return Ray3f(o, -d, mint, maxt); }
    std::string toString() const {
        return fmt::format("Ray3f[o={}, d={}, mint={}, maxt={}]", o.toString(), d.toString(), mint,
                           maxt);
    }
    Point3f operator()(float t) const { return o + t * d; }
};

} // namespace nori
