// Ray intersection against all shapes of a scene (or of a shape group), through two
// BVHs: one over every primitive (triangles of all meshes, spheres), one over instances.
// Triangles are copied into leaf order so a leaf's triangles are contiguous in memory;
// other shapes answer through Shape::rayIntersect. An instance places another Accel (a
// shape group's, or one mesh's for its tmesh copies) through an affine map: the ray is
// carried into the instance's space and that Accel answers, so every distinct geometry
// has one bottom-level BVH however often it is placed (a two-level BVH; PBR 4th ed.
// §7.1.2 "Object Instancing"). Instances nest, up to kMaxInstanceDepth levels.
#pragma once

#include <nori/arrayallocator.h>
#include <nori/bvh.h>
#include <nori/shape.h>
#include <nori/transform.h>
#include <nori/trianglepacket.h>

#include <unordered_map>
#include <vector>

namespace nori {

class Accel {
public:
    /// How many levels of instances may nest (an instance of a group that holds
    /// instances of a group, ...): the size of the path a hit records.
    static constexpr int kMaxInstanceDepth = 8;
    /// An instance test costs a transform and a traversal of the instanced tree: in
    /// units of a box test, about what the top levels of a small tree cost.
    static constexpr float kInstanceIntersectionCost = 8.0f;

    /// What an instance places: the Accel of its geometry, and the shape that hits on it
    /// report instead of the shape hit (a tmesh with its own BSDF reports a copy of its
    /// parent with that BSDF), or nullptr.
    struct InstanceTarget {
        const Accel *accel = nullptr;
        const Shape *reportedShape = nullptr;
    };

    void addShape(const Shape *shape);
    /// Places the target's geometry in this Accel's space by `toWorld` (affine). The
    /// target (and its Accel, built) must outlive this one. Throws when the nesting
    /// would exceed kMaxInstanceDepth.
    void addInstance(const InstanceTarget *target, const AffineMap &toWorld);
    /// Builds the BVHs once all shapes and instances are added. Primitives with
    /// non-finite bounds are left out, and a warning says how many.
    void build();

    /// Closest hit along the ray's segment; with shadowRay, returns at the first hit
    /// and leaves `its` unspecified. Ties in t go to the lower (shape, primitive) index,
    /// then to instances in the order they were added, so the answer does not depend on
    /// the trees. A hit inside an instance is reported in world space.
    bool rayIntersect(const Ray3f &ray, Intersection &its, bool shadowRay) const;
    /// The same closest hit as rayIntersect, reported as its distance, shape and
    /// primitive only (what Embree's rtcIntersect1 returns): no shading information is
    /// computed, for queries that need no more (and for nori-bench's comparison).
    bool closestHit(const Ray3f &ray, float &t, const Shape *&shape, uint32_t &primIndex) const;
    const BoundingBox3f &getBoundingBox() const { return m_bbox; }
    /// The primitive BVH's statistics.
    const BVHBuildStatistics &statistics() const { return m_bvh.statistics(); }
    const BVHBuildStatistics &instanceStatistics() const { return m_instanceBvh.statistics(); }
    size_t instanceCount() const { return m_instances.size(); }
    /// Levels of instances below this Accel: 0 without instances.
    int instanceDepth() const { return m_instanceDepth; }
    /// Bytes this Accel holds once built (nodes, leaf-ordered primitives, instance
    /// records), not counting the Accels its instances place.
    size_t memoryBytes() const;

private:
    /// Which shape and primitive a leaf slot holds.
    struct PrimitiveId {
        uint32_t shapeIndex;
        uint32_t primIndex;
        bool operator<(const PrimitiveId &o) const {
            return shapeIndex != o.shapeIndex ? shapeIndex < o.shapeIndex : primIndex < o.primIndex;
        }
    };
    /// One placement, in the instance BVH's leaf order: 56 bytes.
    struct InstanceRecord {
        AffineMap toLocal; ///< this Accel's space -> the target's
        uint32_t target;   ///< index into m_targets
        uint32_t order;    ///< when it was added, for ties
    };
    /// The closest hit found so far, with the instances it lies in, outermost first.
    struct Hit {
        float t = kInfinity;
        Point2f coords;
        const Accel *owner = nullptr; ///< the Accel whose primitive slot was hit
        uint32_t slot = 0;
        int depth = 0;
        const InstanceRecord *path[kMaxInstanceDepth];
    };

    /// The closest hit (any hit with AnyHit) on the ray's segment, in this Accel's
    /// space; `depth` is the number of instances the ray has entered.
    template <bool AnyHit> bool intersect(const Ray3f &ray, Hit &hit, int depth) const;
    /// Follows the instances a hit lies in: returns the shape the innermost placement
    /// reports (nullptr: the hit shape itself) and, if asked, their composed map from
    /// this Accel's space to the innermost one.
    const Shape *followInstances(const Hit &hit, AffineMap *toLocal) const;
    /// The ray carried into an instance's space, its segment starting past the
    /// origin's rounding error so that a spawned ray cannot re-hit its own surface
    /// there (pbrt-v4 §6.8.6, Transform::ApplyInverse).
    static Ray3f toInstanceSpace(const AffineMap &toLocal, const Ray3f &ray, float tMax);

    std::vector<const Shape *> m_shapes;
    std::vector<uint8_t> m_isMesh;   ///< per shape: a Mesh, tested inline
    std::vector<uint8_t> m_isMasked; ///< per shape: has an alpha mask, asked at each hit
    bool m_hasOpacity = false;       ///< some shape has one
    /// The ids of leaf slot `slot`.
    PrimitiveId idOf(uint32_t slot) const {
        const TrianglePacket &packet = m_packets[slot / TrianglePacket::kWidth];
        const uint32_t lane = slot % TrianglePacket::kWidth;
        return {packet.shapeIndex[lane], packet.primIndex[lane]};
    }

    // The leaf slots in leaf order, four to a packet: triangles' vertices (other kinds of
    // primitive leave their lane NaN) and every slot's ids.
    std::vector<TrianglePacket, LargeArrayAllocator<TrianglePacket>> m_packets;
    BVH<8> m_bvh;

    std::vector<const InstanceTarget *> m_targets;
    std::unordered_map<const InstanceTarget *, uint32_t> m_targetIndex; ///< until build()
    std::vector<InstanceRecord> m_instances;
    std::vector<BoundingBox3f> m_instanceBounds; ///< until build()
    BVH<4> m_instanceBvh;
    int m_instanceDepth = 0;

    BoundingBox3f m_bbox;
};

} // namespace nori
