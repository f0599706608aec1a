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

/// A flattened node: an interior node's two children are the pair at `offset` and
/// `offset + 1`; a leaf holds `count` primitives starting at `offset` in
/// primitiveOrder(). Sibling pairs start at even indices of a 64-byte aligned array,
/// so the two boxes a traversal step tests share one cache line.
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
    /// SAH costs of a primitive test and of a traversal step. A step costs more than its
    /// arithmetic: it is usually a cache miss, so nori-bench's incoherent rays ran fastest
    /// with shallower trees (measured 1, 2, 4 and 8).
    static constexpr float kIntersectionCost = 1.0f;
    static constexpr float kTraversalCost = 4.0f;
    static constexpr int kBinCount = 16;
    static constexpr int kMaxLeafSize = 8;
    /// Below this depth the build stops looking for SAH splits and halves the primitive
    /// list, so no tree is deeper than kMaxDepth (the traversal stack's size).
    static constexpr int kSahDepthLimit = 64;
    static constexpr int kMaxDepth = 128;

    /// Builds over primitives with the given bounds (primitive i has bounds[i]).
    /// Primitives with empty or non-finite bounds are left out and counted.
    /// `intersectionCost` is a primitive test's cost in units of a box test (an instance,
    /// whose test is a whole traversal, costs more than a triangle).
    void build(const std::vector<BoundingBox3f> &bounds,
               float intersectionCost = kIntersectionCost);

    /// Leaf slot -> index of the primitive passed to build().
    const std::vector<uint32_t> &primitiveOrder() const { return m_primitiveOrder; }
    /// Hands over primitiveOrder() once the caller has put its data in leaf order; the
    /// tree no longer needs it.
    std::vector<uint32_t> takePrimitiveOrder() { return std::move(m_primitiveOrder); }
    const BVHNode &node(size_t index) const { return m_nodes[index]; }
    size_t nodeCount() const { return m_nodes.size(); }
    const BVHBuildStatistics &statistics() const { return m_statistics; }
    BoundingBox3f getBoundingBox() const;

    /// Visits the leaves the ray's segment [ray.mint, tMax] reaches, nearest child first.
    /// `intersect(slot, tMax)` tests the primitive in leaf slot `slot`; on a hit it lowers
    /// tMax and returns true. With anyHit, traversal stops at the first hit.
    /// `prefetch(slot)` is called for the first slot of a leaf that will be visited later,
    /// so the caller can bring that primitive's data into the cache meanwhile.
    template <typename IntersectPrimitive, typename PrefetchPrimitive>
    bool traverse(const Ray3f &ray, float &tMax, bool anyHit, IntersectPrimitive &&intersect,
                  PrefetchPrimitive &&prefetch) const;

private:
    /// std::allocator for over-aligned memory: the node array starts on a cache line.
    template <typename T> struct CacheLineAllocator {
        using value_type = T;
        CacheLineAllocator() = default;
        template <typename U> CacheLineAllocator(const CacheLineAllocator<U> &) {}
        T *allocate(size_t n) {
            return static_cast<T *>(::operator new(n * sizeof(T), std::align_val_t(64)));
        }
        void deallocate(T *p, size_t) { ::operator delete(p, std::align_val_t(64)); }
        bool operator==(const CacheLineAllocator &) const { return true; }
        bool operator!=(const CacheLineAllocator &) const { return false; }
    };

    std::vector<BVHNode, CacheLineAllocator<BVHNode>> m_nodes;
    std::vector<uint32_t> m_primitiveOrder;
    BVHBuildStatistics m_statistics;
};

template <typename IntersectPrimitive, typename PrefetchPrimitive>
bool BVH::traverse(const Ray3f &ray, float &tMax, bool anyHit, IntersectPrimitive &&intersect,
                   PrefetchPrimitive &&prefetch) const {
    if (m_nodes.empty())
        return false;
    // Per ray: for each axis, which of a node's two planes is entered first (the node's
    // floats are min x,y,z at 0..2 and max x,y,z at 4..6) and o/d, so that the slab
    // distance (plane − o)/d is one multiply-subtract.
    const Vector3f &invDir = ray.dRcp;
    int nearPlane[3], farPlane[3];
    float originScaled[3];
    for (int axis = 0; axis < 3; ++axis) {
        nearPlane[axis] = invDir[axis] < 0.0f ? 4 + axis : axis;
        farPlane[axis] = invDir[axis] < 0.0f ? axis : 4 + axis;
        originScaled[axis] = ray.o[axis] * invDir[axis];
    }
    // Widening the far distance by 2γ₃ keeps the slab test conservative under rounding
    // (PBR 4th ed. §6.8.2). A zero direction component gives ±inf distances (NaN when
    // the origin lies on the plane, which the max/min below then ignore).
    constexpr float kFarScale = 1.0f + 2.0f * gammaBound(3);
    auto entryDistance = [&](const BVHNode &node, float tLimit) {
        const float *planes = node.boundsMin;
        float tNear = ray.mint, tFar = tLimit;
        for (int axis = 0; axis < 3; ++axis) {
            const float t0 = planes[nearPlane[axis]] * invDir[axis] - originScaled[axis];
            const float t1 =
                (planes[farPlane[axis]] * invDir[axis] - originScaled[axis]) * kFarScale;
            tNear = t0 > tNear ? t0 : tNear;
            tFar = t1 < tFar ? t1 : tFar;
        }
        return tNear <= tFar ? tNear : kInfinity;
    };

    if (entryDistance(m_nodes[0], tMax) == kInfinity)
        return false;
    // The stack holds nodes whose box the ray entered at the recorded distance.
    struct Entry {
        uint32_t node;
        float tEntry;
    };
    Entry stack[kMaxDepth];
    int stackSize = 0;
    uint32_t current = 0;
    bool hit = false;
    while (true) {
        const BVHNode &node = m_nodes[current];
        if (node.count == 0) {
            // Test both children and descend into the nearer; the farther waits.
            const uint32_t first = node.offset, second = node.offset + 1;
            const float tFirst = entryDistance(m_nodes[first], tMax);
            const float tSecond = entryDistance(m_nodes[second], tMax);
            if (tFirst != kInfinity && tSecond != kInfinity) {
                const bool firstIsNearer = tFirst <= tSecond;
                const uint32_t farther = firstIsNearer ? second : first;
                stack[stackSize++] = Entry{farther, firstIsNearer ? tSecond : tFirst};
                current = firstIsNearer ? first : second;
                // The farther child's content is needed after the nearer subtree: fetch it
                // into the cache now, overlapping the memory latency with that work.
                const BVHNode &fartherNode = m_nodes[farther];
                if (fartherNode.count == 0)
                    __builtin_prefetch(&m_nodes[fartherNode.offset]);
                else
                    prefetch(fartherNode.offset);
                continue;
            }
            if (tFirst != kInfinity) {
                current = first;
                continue;
            }
            if (tSecond != kInfinity) {
                current = second;
                continue;
            }
        } else {
            for (uint32_t slot = node.offset; slot < node.offset + node.count; ++slot) {
                if (intersect(slot, tMax)) {
                    hit = true;
                    if (anyHit)
                        return true;
                }
            }
        }
        // Pop the next node the ray still reaches: a hit found since it was pushed may
        // lie before its box.
        do {
            if (stackSize == 0)
                return hit;
            --stackSize;
        } while (stack[stackSize].tEntry > tMax);
        current = stack[stackSize].node;
    }
}

} // namespace nori
