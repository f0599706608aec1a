// Axis-aligned bounding boxes.
#pragma once

#include <nori/ray.h>

namespace nori {

struct BoundingBox3f {
    Point3f min = Point3f(kInfinity);
    Point3f max = Point3f(-kInfinity);

    BoundingBox3f() = default;
    explicit BoundingBox3f(const Point3f &p) : min(p), max(p) {}
    BoundingBox3f(const Point3f &min, const Point3f &max) : min(min), max(max) {}

    bool isValid() const { return (max.array() >= min.array()).all(); }
    void expandBy(const Point3f &p) {
        min = min.cwiseMin(p);
        max = max.cwiseMax(p);
    }
    void expandBy(const BoundingBox3f &box) {
        min = min.cwiseMin(box.min);
        max = max.cwiseMax(box.max);
    }
    Point3f getCenter() const { return (min + max) * 0.5f; }
    Vector3f getExtents() const { return max - min; }
    bool contains(const Point3f &p) const {
        return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
    }
    float getSurfaceArea() const {
        Vector3f e = getExtents();
        return 2.0f * (e.x() * e.y() + e.y() * e.z() + e.z() * e.x());
    }
    /// Slab test; returns the parametric overlap [nearT, farT] with the ray's segment.
    bool rayIntersect(const Ray3f &ray, float &nearT, float &farT) const {
        nearT = ray.mint;
        farT = ray.maxt;
        for (int i = 0; i < 3; ++i) {
            float t0 = (min[i] - ray.o[i]) * ray.dRcp[i];
            float t1 = (max[i] - ray.o[i]) * ray.dRcp[i];
            if (t0 > t1)
                std::swap(t0, t1);
            nearT = std::max(nearT, t0);
            farT = std::min(farT, t1);
            if (!(nearT <= farT))
                return false;
        }
        return true;
    }
};

} // namespace nori
