// A bounding volume hierarchy over abstract primitives (given by their bounding boxes):
// binned SAH build in parallel (Wald, "On fast Construction of SAH-based Bounding Volume
// Hierarchies", 2007), flattened depth-first into 32-byte nodes, traversed near child
// first with an explicit stack (PBR 4th ed. §7.3). What a primitive is stays with the
// caller, so the same BVH serves triangles, spheres and, later, instances.
#pragma once

#include <nori/bbox.h>
#include <nori/rayerror.h>

#include <vector>

namespace nori {

/// A flattened node: an interior node's first child follows it directly, the second is
/// at `offset`; a leaf holds `count` primitives starting at `offset` in primitiveOrder().
struct alignas(32) BVHNode {
    float boundsMin[3];
    uint32_t offset;
    float boundsMax[3];
    uint16_t count; ///< 0 for interior nodes
    uint16_t axis;  ///< split axis of an interior node
};
static_assert(sizeof(BVHNode) == 32, "BVH nodes must stay 32 bytes");

struct BVHBuildStatistics {
    size_t primitives = 0;        ///< primitives in the tree
    size_t skippedPrimitives = 0; ///< left out for empty or non-finite bounds
    size_t nodes = 0;
    size_t leaves = 0;
    size_t maxDepth = 0;
    float sahCost = 0.0f; ///< expected cost of a random ray, in units of one box test
};

class BVH {
public:
    /// SAH cost of intersecting one primitive, relative to one node traversal step.
    static constexpr float kIntersectionCost = 1.0f;
    static constexpr float kTraversalCost = 1.0f;
    static constexpr int kBinCount = 16;
    static constexpr int kMaxLeafSize = 8;
    /// Below this depth the build stops looking for SAH splits and halves the primitive
    /// list, so no tree is deeper than kMaxDepth (the traversal stack's size).
    static constexpr int kSahDepthLimit = 64;
    static constexpr int kMaxDepth = 128;

    /// Builds over primitives with the given bounds (primitive i has bounds[i]).
    /// Primitives with empty or non-finite bounds are left out and counted.
    void build(const std::vector<BoundingBox3f> &bounds);

    /// Leaf slot -> index of the primitive passed to build().
    const std::vector<uint32_t> &primitiveOrder() const { return m_primitiveOrder; }
    const std::vector<BVHNode> &nodes() const { return m_nodes; }
    const BVHBuildStatistics &statistics() const { return m_statistics; }
    BoundingBox3f getBoundingBox() const;

    /// Visits the leaves the ray's segment [ray.mint, tMax] reaches, nearest child first.
    /// `intersect(slot, tMax)` tests the primitive in leaf slot `slot`; on a hit it lowers
    /// tMax and returns true. With anyHit, traversal stops at the first hit.
    template <typename IntersectPrimitive>
    bool traverse(const Ray3f &ray, float &tMax, bool anyHit, IntersectPrimitive &&intersect) const;

private:
    std::vector<BVHNode> m_nodes;
    std::vector<uint32_t> m_primitiveOrder;
    BVHBuildStatistics m_statistics;
};

template <typename IntersectPrimitive>
bool BVH::traverse(const Ray3f &ray, float &tMax, bool anyHit,
                   IntersectPrimitive &&intersect) const {
    if (m_nodes.empty())
        return false;
    const Vector3f &invDir = ray.dRcp;
    const int dirIsNeg[3] = {invDir.x() < 0.0f, invDir.y() < 0.0f, invDir.z() < 0.0f};
    // Widening the far distance by 2γ₃ keeps the slab test conservative under rounding
    // (PBR 4th ed. §6.8.2).
    constexpr float kFarScale = 1.0f + 2.0f * gammaBound(3);

    uint32_t stack[kMaxDepth];
    int stackSize = 0;
    uint32_t current = 0;
    bool hit = false;
    while (true) {
        const BVHNode &node = m_nodes[current];
        // Slab test; for a zero direction component the products are ±inf (or NaN when
        // the origin lies on the slab, which the comparisons then ignore).
        float tNear = ray.mint, tFar = tMax;
        for (int axis = 0; axis < 3; ++axis) {
            const float lo = dirIsNeg[axis] ? node.boundsMax[axis] : node.boundsMin[axis];
            const float hi = dirIsNeg[axis] ? node.boundsMin[axis] : node.boundsMax[axis];
            const float t0 = (lo - ray.o[axis]) * invDir[axis];
            const float t1 = (hi - ray.o[axis]) * invDir[axis] * kFarScale;
            if (t0 > tNear)
                tNear = t0;
            if (t1 < tFar)
                tFar = t1;
        }
        if (tNear <= tFar) {
            if (node.count > 0) {
                for (uint32_t slot = node.offset; slot < node.offset + node.count; ++slot) {
                    if (intersect(slot, tMax)) {
                        hit = true;
                        if (anyHit)
                            return true;
                    }
                }
            } else if (dirIsNeg[node.axis]) {
                // The second child lies first along the ray.
                stack[stackSize++] = current + 1;
                current = node.offset;
                continue;
            } else {
                stack[stackSize++] = node.offset;
                current = current + 1;
                continue;
            }
        }
        if (stackSize == 0)
            break;
        current = stack[--stackSize];
    }
    return hit;
}

} // namespace nori
