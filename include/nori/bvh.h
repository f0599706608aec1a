// A bounding volume hierarchy over abstract primitives (given by their bounding boxes):
// a binary tree built by binned SAH in parallel (Wald, "On fast Construction of SAH-based
// Bounding Volume Hierarchies", 2007), collapsed into 4-wide nodes whose four boxes one
// ray tests at once with SSE (Wald, Benthin and Boulos, "Getting Rid of Packets", 2008),
// traversed nearest child first with an explicit stack (PBR 4th ed. §7.3). What a
// primitive is stays with the caller, so the same BVH serves triangles, spheres and
// instances.
#pragma once

#include <nori/arrayallocator.h>
#include <nori/bbox.h>
#include <nori/rayerror.h>

#include <immintrin.h>

#include <algorithm>
#include <vector>

namespace nori {

/// A node of four children, 128 bytes on two cache lines. Its children's boxes are
/// stored here as structures of arrays, so that one SSE instruction tests a plane of all
/// four. A child is a reference: an interior node's index, or a leaf (kLeafFlag) with
/// its primitive count and the first of its primitive slots. Unused slots are empty
/// leaves with empty boxes (min +inf, max -inf), which no ray enters.
struct alignas(64) BVHNode {
    static constexpr int kWidth = 4;
    static constexpr uint32_t kLeafFlag = 0x80000000u;
    static constexpr int kCountShift = 27; ///< bits 27-30 of a leaf: primitive count
    static constexpr uint32_t kSlotMask = (1u << kCountShift) - 1;

    static bool isLeaf(uint32_t child) { return (child & kLeafFlag) != 0; }
    static uint32_t leafCount(uint32_t child) { return (child & ~kLeafFlag) >> kCountShift; }
    static uint32_t leafFirst(uint32_t child) { return child & kSlotMask; }
    static uint32_t makeLeaf(uint32_t first, uint32_t count) {
        return kLeafFlag | (count << kCountShift) | first;
    }

    /// bounds[axis][0][i] and bounds[axis][1][i]: child i's minimum and maximum on axis.
    float bounds[3][2][kWidth];
    uint32_t child[kWidth];
    uint8_t padding[16];

    BoundingBox3f childBounds(int i) const {
        return BoundingBox3f(Point3f(bounds[0][0][i], bounds[1][0][i], bounds[2][0][i]),
                             Point3f(bounds[0][1][i], bounds[1][1][i], bounds[2][1][i]));
    }
};
static_assert(sizeof(BVHNode) == 128, "BVH nodes must stay two cache lines");

struct BVHBuildStatistics {
    size_t primitives = 0;        ///< primitives in the tree
    size_t skippedPrimitives = 0; ///< left out for empty or non-finite bounds
    size_t nodes = 0;             ///< 4-wide nodes
    size_t leaves = 0;
    size_t maxDepth = 0;  ///< of the 4-wide tree
    float sahCost = 0.0f; ///< expected cost of a random ray, in units of one box test
};

class BVH {
public:
    /// SAH costs of a primitive test and of a traversal step. A step costs more than its
    /// arithmetic: it is usually a cache miss, so nori-bench's incoherent rays ran fastest
    /// with shallower trees.
    static constexpr float kIntersectionCost = 1.0f;
    static constexpr float kTraversalCost = 4.0f;
    static constexpr int kBinCount = 16;
    static constexpr int kMaxLeafSize = 8;
    /// Below this depth the build stops looking for SAH splits and halves the primitive
    /// list, so no binary tree (and so no wide tree) is deeper than kMaxDepth.
    static constexpr int kSahDepthLimit = 64;
    static constexpr int kMaxDepth = 128;
    /// A padding entry of primitiveOrder().
    static constexpr uint32_t kNoPrimitive = 0xFFFFFFFFu;

    /// Builds over primitives with the given bounds (primitive i has bounds[i]).
    /// Primitives with empty or non-finite bounds are left out and counted.
    /// `intersectionCost` is a primitive test's cost in units of a box test (an instance,
    /// whose test is a whole traversal, costs more than a triangle). Every leaf's first
    /// slot is a multiple of `leafAlignment` (padding slots hold kNoPrimitive), so that a
    /// caller can store its primitives in SIMD packets of that many.
    void build(const std::vector<BoundingBox3f> &bounds, float intersectionCost = kIntersectionCost,
               uint32_t leafAlignment = 1);

    /// Leaf slot -> index of the primitive passed to build(), or kNoPrimitive.
    const std::vector<uint32_t> &primitiveOrder() const { return m_primitiveOrder; }
    /// Hands over primitiveOrder() once the caller has put its data in leaf order; the
    /// tree no longer needs it.
    std::vector<uint32_t> takePrimitiveOrder() { return std::move(m_primitiveOrder); }
    const BVHNode &node(size_t index) const { return m_nodes[index]; }
    size_t nodeCount() const { return m_nodes.size(); }
    const BVHBuildStatistics &statistics() const { return m_statistics; }
    const BoundingBox3f &getBoundingBox() const { return m_bounds; }

    /// Visits the leaves the ray's segment [ray.mint, tMax] reaches. Closest-hit
    /// traversal takes a node's children nearest first; with anyHit it takes them in
    /// stored order, largest box first (the likeliest to hold an occluder), and stops at
    /// the first hit. `intersectLeaf(first, count, tMax)` tests the leaf's primitives in
    /// slots [first, first + count); on a hit it lowers tMax and returns true.
    template <typename IntersectLeaf>
    bool traverse(const Ray3f &ray, float &tMax, bool anyHit, IntersectLeaf &&intersectLeaf) const;

private:
    /// Each visit pushes at most kWidth − 1 children, once per level.
    static constexpr int kStackSize = (BVHNode::kWidth - 1) * kMaxDepth + 1;

    std::vector<BVHNode, LargeArrayAllocator<BVHNode>> m_nodes;
    std::vector<uint32_t> m_primitiveOrder;
    BoundingBox3f m_bounds;
    BVHBuildStatistics m_statistics;
};

template <typename IntersectLeaf>
bool BVH::traverse(const Ray3f &ray, float &tMax, bool anyHit,
                   IntersectLeaf &&intersectLeaf) const {
    if (m_nodes.empty())
        return false;
    // Per ray: for each axis, which of a node's two planes is entered first, and o/d, so
    // that the slab distance (plane − o)/d is one multiply and one subtraction.
    __m128 invDir[3], originScaled[3];
    int nearSide[3];
    for (int axis = 0; axis < 3; ++axis) {
        invDir[axis] = _mm_set1_ps(ray.dRcp[axis]);
        originScaled[axis] = _mm_set1_ps(ray.o[axis] * ray.dRcp[axis]);
        nearSide[axis] = ray.dRcp[axis] < 0.0f ? 1 : 0;
    }
    // Widening the far distance by 2γ₃ keeps the slab test conservative under rounding
    // (PBR 4th ed. §6.8.2). A zero direction component gives ±inf distances (NaN when the
    // origin lies on the plane): _mm_max_ps/_mm_min_ps return their second operand for a
    // NaN, so such a plane leaves the running interval as it was.
    const __m128 farScale = _mm_set1_ps(1.0f + 2.0f * gammaBound(3));
    const __m128 segmentStart = _mm_set1_ps(ray.mint);

    struct Entry {
        uint32_t child;
        float tEntry;
    };
    Entry stack[kStackSize];
    int stackSize = 0;
    uint32_t current = 0; // the root node
    bool hit = false;
    while (true) {
        if (!BVHNode::isLeaf(current)) {
            const BVHNode &node = m_nodes[current];
            __m128 tNear = segmentStart, tFar = _mm_set1_ps(tMax);
            for (int axis = 0; axis < 3; ++axis) {
                const __m128 nearPlane = _mm_load_ps(node.bounds[axis][nearSide[axis]]);
                const __m128 farPlane = _mm_load_ps(node.bounds[axis][1 - nearSide[axis]]);
                const __m128 t0 =
                    _mm_sub_ps(_mm_mul_ps(nearPlane, invDir[axis]), originScaled[axis]);
                const __m128 t1 = _mm_mul_ps(
                    _mm_sub_ps(_mm_mul_ps(farPlane, invDir[axis]), originScaled[axis]), farScale);
                tNear = _mm_max_ps(t0, tNear);
                tFar = _mm_min_ps(t1, tFar);
            }
            unsigned entered = static_cast<unsigned>(_mm_movemask_ps(_mm_cmple_ps(tNear, tFar)));
            if (entered != 0) {
                alignas(16) float distance[BVHNode::kWidth];
                _mm_store_ps(distance, tNear);
                const int first = __builtin_ctz(entered);
                entered &= entered - 1;
                if (entered == 0) { // one child: no stack traffic
                    current = node.child[first];
                    continue;
                }
                // Several children: push them so that the one to visit next is on top.
                // Closest hit: sorted by entry distance, farthest pushed first (insertion
                // sort of at most four); any hit: in stored order, so reversed on the stack.
                const int base = stackSize;
                stack[stackSize++] = Entry{node.child[first], distance[first]};
                while (entered != 0) {
                    const int i = __builtin_ctz(entered);
                    entered &= entered - 1;
                    const Entry entry{node.child[i], distance[i]};
                    int position = stackSize++;
                    for (; !anyHit && position > base && stack[position - 1].tEntry < entry.tEntry;
                         --position)
                        stack[position] = stack[position - 1];
                    stack[position] = entry;
                }
                if (anyHit)
                    std::reverse(stack + base, stack + stackSize);
                // The children left on the stack are needed later: bring them into the
                // cache now, overlapping the memory latency with the nearest subtree.
                for (int i = base; i + 1 < stackSize; ++i)
                    if (!BVHNode::isLeaf(stack[i].child)) {
                        const char *address =
                            reinterpret_cast<const char *>(&m_nodes[stack[i].child]);
                        __builtin_prefetch(address);
                        __builtin_prefetch(address + 64);
                    }
                current = stack[--stackSize].child;
                continue;
            }
        } else if (const uint32_t count = BVHNode::leafCount(current);
                   count > 0 && intersectLeaf(BVHNode::leafFirst(current), count, tMax)) {
            hit = true;
            if (anyHit)
                return true;
        }
        // Pop the next child the ray still reaches: a hit found since it was pushed may
        // lie before its box.
        do {
            if (stackSize == 0)
                return hit;
            --stackSize;
        } while (stack[stackSize].tEntry > tMax);
        current = stack[stackSize].child;
    }
}

} // namespace nori
