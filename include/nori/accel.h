// Ray intersection against all shapes of a scene, through one BVH over every primitive
// (triangles of all meshes, spheres). Triangles are copied into leaf order so a leaf's
// triangles are contiguous in memory; other shapes answer through Shape::rayIntersect.
#pragma once

#include <nori/bvh.h>
#include <nori/shape.h>

#include <vector>

namespace nori {

class Accel {
public:
    void addShape(const Shape *shape);
    /// Builds the BVH once all shapes are added. Primitives with non-finite bounds are
    /// left out, and a warning says how many.
    void build();

    /// Closest hit along the ray's segment; with shadowRay, returns at the first hit
    /// and leaves `its` unspecified. Ties in t go to the lower (shape, primitive) index,
    /// so the answer does not depend on the tree.
    bool rayIntersect(const Ray3f &ray, Intersection &its, bool shadowRay) const;
    const BoundingBox3f &getBoundingBox() const { return m_bbox; }
    const BVHBuildStatistics &statistics() const { return m_bvh.statistics(); }

private:
    /// A triangle's vertices, in leaf order. Other kinds of primitive have a NaN p0.x
    /// (meshes have no non-finite vertices: Mesh drops such triangles), which saves a
    /// separate flag and the cache miss of reading it.
    struct TriangleVertices {
        Point3f p0, p1, p2;
        bool isTriangle() const { return !std::isnan(p0.x()); }
    };
    /// Which shape and primitive a leaf slot holds; read only for the hit.
    struct PrimitiveId {
        uint32_t shapeIndex;
        uint32_t primIndex;
        bool operator<(const PrimitiveId &o) const {
            return shapeIndex != o.shapeIndex ? shapeIndex < o.shapeIndex : primIndex < o.primIndex;
        }
    };

    std::vector<const Shape *> m_shapes;
    std::vector<uint8_t> m_isMesh; ///< per shape: a Mesh, tested inline
    // Per leaf slot, split by how often traversal reads them (memory, not compute,
    // bounds incoherent rays): vertices for every test, ids only for the closest hit.
    std::vector<TriangleVertices> m_triangles;
    std::vector<PrimitiveId> m_ids;
    BVH m_bvh;
    BoundingBox3f m_bbox;
};

} // namespace nori
