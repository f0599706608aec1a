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

    // Nori 2's TBoundingBox interface, for course code.
    bool operator==(const BoundingBox3f &box) const { return min == box.min && max == box.max; }
    bool operator!=(const BoundingBox3f &box) const { return !operator==(box); }
    float getVolume() const { return getExtents().prod(); }
    bool isPoint() const { return min == max; }
    bool hasVolume() const { return (max.array() > min.array()).all(); }
    int getMajorAxis() const {
        const Vector3f e = getExtents();
        int axis = 0;
        for (int i = 1; i < 3; ++i)
            if (e[i] > e[axis])
                axis = i;
        return axis;
    }
    int getLargestAxis() const { return getMajorAxis(); }
    int getMinorAxis() const {
        const Vector3f e = getExtents();
        int axis = 0;
        for (int i = 1; i < 3; ++i)
            if (e[i] < e[axis])
                axis = i;
        return axis;
    }
    /// Corner i: bit k of i chooses max (1) or min (0) along axis k.
    Point3f getCorner(int index) const {
        return Point3f((index & 1) ? max.x() : min.x(), (index & 2) ? max.y() : min.y(),
                       (index & 4) ? max.z() : min.z());
    }
    void reset() { *this = BoundingBox3f(); }
    void clip(const BoundingBox3f &box) {
        min = min.cwiseMax(box.min);
        max = max.cwiseMin(box.max);
    }
    static BoundingBox3f merge(const BoundingBox3f &a, const BoundingBox3f &b) {
        return BoundingBox3f(a.min.cwiseMin(b.min), a.max.cwiseMax(b.max));
    }
    bool contains(const Point3f &p, bool strict) const {
        return strict ? (p.array() > min.array()).all() && (p.array() < max.array()).all()
                      : contains(p);
    }
    bool contains(const BoundingBox3f &box, bool strict = false) const {
        return strict
                   ? (box.min.array() > min.array()).all() && (box.max.array() < max.array()).all()
                   : (box.min.array() >= min.array()).all() &&
                         (box.max.array() <= max.array()).all();
    }
    bool overlaps(const BoundingBox3f &box, bool strict = false) const {
        return strict
                   ? (box.min.array() < max.array()).all() && (box.max.array() > min.array()).all()
                   : (box.min.array() <= max.array()).all() &&
                         (box.max.array() >= min.array()).all();
    }
    float squaredDistanceTo(const Point3f &p) const {
        const Vector3f below = (min - p).cwiseMax(0.0f), above = (p - max).cwiseMax(0.0f);
        return (below + above).squaredNorm();
    }
    float distanceTo(const Point3f &p) const { return std::sqrt(squaredDistanceTo(p)); }
    float squaredDistanceTo(const BoundingBox3f &box) const {
        const Vector3f below = (min - box.max).cwiseMax(0.0f),
                       above = (box.min - max).cwiseMax(0.0f);
        return (below + above).squaredNorm();
    }
    float distanceTo(const BoundingBox3f &box) const { return std::sqrt(squaredDistanceTo(box)); }
    /// Whether the ray's segment meets the box.
    bool rayIntersect(const Ray3f &ray) const {
        float nearT, farT;
        return rayIntersect(ray, nearT, farT);
    }
    std::string toString() const {
        return fmt::format("BoundingBox3f[min={}, max={}]", min.toString(), max.toString());
    }
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
