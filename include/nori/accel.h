// Ray intersection against all shapes of a scene. The interface is the one the BVH
// implements; this version tests every primitive (a temporary brute-force loop).
#pragma once

#include <nori/shape.h>

#include <vector>

namespace nori {

class Accel {
public:
    void addShape(const Shape *shape);
    /// Builds the acceleration structure once all shapes are added.
    void build();

    /// Closest hit along the ray's segment; with shadowRay, returns at the first hit
    /// and leaves `its` unspecified.
    bool rayIntersect(const Ray3f &ray, Intersection &its, bool shadowRay) const;
    const BoundingBox3f &getBoundingBox() const { return m_bbox; }

private:
    std::vector<const Shape *> m_shapes;
    BoundingBox3f m_bbox;
};

} // namespace nori
