// A bounding volume hierarchy over abstract primitives (given by their bounding boxes):
// a binary tree built by binned SAH in parallel (Wald, "On fast Construction of SAH-based
// Bounding Volume Hierarchies", 2007), collapsed into wide nodes (8 children for
// triangles, 4 for instances) at the least SAH cost (Ylitie, Karras and Laine, HPG 2017)
// whose boxes one ray tests at once with AVX or SSE (Wald, Benthin and Boulos, "Getting
// Rid of Packets", 2008),
// traversed nearest child first with an explicit stack (PBR 4th ed. §7.3). What a
// primitive is stays with the caller, so the same BVH serves triangles, spheres and
// instances.
#pragma once

#include <nori/arrayallocator.h>
#include <nori/bbox.h>
#include <nori/rayerror.h>
#include <nori/simd.h>

#include <algorithm>
#include <functional>
#include <vector>

namespace nori {

/// A child reference of a wide node: an interior node's index, or a leaf (kLeafFlag)
/// with its primitive count and the first of its primitive slots.
struct BVHReference {
    static constexpr uint32_t kLeafFlag = 0x80000000u;
    static constexpr int kCountShift = 27; ///< bits 27-30 of a leaf: primitive count
    static constexpr uint32_t kSlotMask = (1u << kCountShift) - 1;
    static constexpr uint32_t kMaxLeafCount = (kLeafFlag >> kCountShift) - 1;

    static bool isLeaf(uint32_t child) { return (child & kLeafFlag) != 0; }
    static uint32_t leafCount(uint32_t child) { return (child & ~kLeafFlag) >> kCountShift; }
    static uint32_t leafFirst(uint32_t child) { return child & kSlotMask; }
    static uint32_t makeLeaf(uint32_t first, uint32_t count) {
        return kLeafFlag | (count << kCountShift) | first;
    }
};

/// A node of Width children, 32·Width bytes on whole cache lines (8 children: four
/// lines). Its children's boxes are stored as structures of arrays, so that one SIMD
/// instruction tests a plane of four or eight children. Unused slots are empty leaves
/// with empty boxes (min +inf, max -inf), which no ray enters.
template <int Width> struct alignas(64) BVHNode {
    static constexpr int kWidth = Width;

    /// bounds[axis][0][i] and bounds[axis][1][i]: child i's minimum and maximum on axis.
    float bounds[3][2][kWidth];
    uint32_t child[kWidth]; ///< BVHReference
    uint8_t padding[4 * kWidth];

    BoundingBox3f childBounds(int i) const {
        return BoundingBox3f(Point3f(bounds[0][0][i], bounds[1][0][i], bounds[2][0][i]),
                             Point3f(bounds[0][1][i], bounds[1][1][i], bounds[2][1][i]));
    }
};
static_assert(sizeof(BVHNode<4>) == 128 && sizeof(BVHNode<8>) == 256,
              "BVH nodes must fill whole cache lines");

/// A ray's slab test against the boxes of a node (PBR 4th ed. §6.1.2): SSE over four
/// children at a time, or AVX over eight when the build targets it.
template <int Width> class NodeRay {
public:
    explicit NodeRay(const Ray3f &ray);

    /// Bit i set: the segment [ray.mint, tMax] enters child i's box, at distance[i].
    unsigned intersect(const BVHNode<Width> &node, float tMax, float *distance) const;

private:
#ifdef __AVX__
    static constexpr int kLanes = Width % 8 == 0 ? 8 : 4;
#else
    static constexpr int kLanes = 4;
#endif
    static_assert(Width % kLanes == 0, "a node's width is a multiple of the SIMD width");
    using Simd = SimdFloats<kLanes>;
    using Lanes = typename Simd::Type;
    Lanes m_invDir[3], m_origin[3], m_farScale, m_segmentStart;
    int m_nearSide[3];
};

struct BVHBuildStatistics {
    size_t primitives = 0;        ///< primitives in the tree
    size_t skippedPrimitives = 0; ///< left out for empty or non-finite bounds
    size_t nodes = 0;             ///< wide nodes
    size_t leaves = 0;
    size_t maxDepth = 0;  ///< of the wide tree
    float sahCost = 0.0f; ///< expected cost of a random ray, in units of one box test
};

/// What BVHs of every width share: the build's parameters, the leaf slots' order, the
/// bounds and the statistics.
class BVHBase {
public:
    /// SAH costs of a primitive test and of a traversal step. A step costs more than its
    /// arithmetic: it is usually a cache miss, so nori-bench's incoherent rays ran fastest
    /// with shallower trees.
    static constexpr float kIntersectionCost = 1.0f;
    static constexpr float kTraversalCost = 4.0f;
    static constexpr int kBinCount = 16;
    static constexpr int kMaxLeafSize = 8;
    static_assert(kMaxLeafSize <= static_cast<int>(BVHReference::kMaxLeafCount),
                  "a leaf reference holds its count in four bits");
    /// Below this depth the build stops looking for SAH splits and halves the primitive
    /// list, so no binary tree (and so no wide tree) is deeper than kMaxDepth.
    static constexpr int kSahDepthLimit = 64;
    static constexpr int kMaxDepth = 128;
    /// A padding entry of primitiveOrder().
    static constexpr uint32_t kNoPrimitive = 0xFFFFFFFFu;

    /// Leaf slot -> index of the primitive passed to build(), or kNoPrimitive.
    const std::vector<uint32_t> &primitiveOrder() const { return m_primitiveOrder; }
    /// Hands over primitiveOrder() once the caller has put its data in leaf order; the
    /// tree no longer needs it.
    std::vector<uint32_t> takePrimitiveOrder() { return std::move(m_primitiveOrder); }
    const BVHBuildStatistics &statistics() const { return m_statistics; }
    const BoundingBox3f &getBoundingBox() const { return m_bounds; }

protected:
    std::vector<uint32_t> m_primitiveOrder;
    BoundingBox3f m_bounds;
    BVHBuildStatistics m_statistics;
};

/// The tree itself, of nodes with Width children: 8 for triangles (fewer levels, so
/// fewer dependent cache misses per ray), 4 for instances (one or two to a leaf, which
/// leaves 8-wide nodes so empty that they measured 146 bytes per instance, over the
/// 128-byte budget; 4-wide ones, 119).
template <int Width> class BVH : public BVHBase {
public:
    using Node = BVHNode<Width>;

    /// Builds over `count` primitives, primitive i with bounds boundsOf(i) (called once
    /// for each, from several threads). Primitives with empty or non-finite bounds are
    /// left out and counted. `intersectionCost` is a primitive test's cost in units of a
    /// box test (an instance, whose test is a whole traversal, costs more than a
    /// triangle). Every leaf's first slot is a multiple of `leafAlignment` (padding slots
    /// hold kNoPrimitive), so that a caller can store its primitives in SIMD packets of
    /// that many.
    void build(size_t count, const std::function<BoundingBox3f(size_t)> &boundsOf,
               float intersectionCost = kIntersectionCost, uint32_t leafAlignment = 1);
    /// The same over primitives whose bounds are given: primitive i has bounds[i].
    void build(const std::vector<BoundingBox3f> &bounds, float intersectionCost = kIntersectionCost,
               uint32_t leafAlignment = 1) {
        build(
            bounds.size(), [&](size_t i) { return bounds[i]; }, intersectionCost, leafAlignment);
    }

    const Node &node(size_t index) const { return m_nodes[index]; }
    size_t nodeCount() const { return m_nodes.size(); }

    /// Visits the leaves the ray's segment [ray.mint, tMax] reaches. Closest-hit
    /// traversal takes a node's children nearest first; AnyHit traversal takes them in
    /// stored order, largest box first (the likeliest to hold an occluder), and stops at
    /// the first hit. `intersectLeaf(first, count, tMax)` tests the leaf's primitives in
    /// slots [first, first + count); on a hit it lowers tMax and returns true.
    /// `prefetchLeaf(first, count)` is called for a leaf put on the stack, so that the
    /// caller can bring its primitives into the cache while nearer children are tested.
    template <bool AnyHit, typename IntersectLeaf, typename PrefetchLeaf>
    bool traverse(const Ray3f &ray, float &tMax, IntersectLeaf &&intersectLeaf,
                  PrefetchLeaf &&prefetchLeaf) const;

private:
    /// Each visit pushes at most Width − 1 children, once per level.
    static constexpr int kStackSize = (Width - 1) * kMaxDepth + 1;

    std::vector<Node, LargeArrayAllocator<Node>> m_nodes;
};

template <int Width>
template <bool AnyHit, typename IntersectLeaf, typename PrefetchLeaf>
bool BVH<Width>::traverse(const Ray3f &ray, float &tMax, IntersectLeaf &&intersectLeaf,
                          PrefetchLeaf &&prefetchLeaf) const {
    if (m_nodes.empty())
        return false;
    const NodeRay<Width> nodeRay(ray);
    struct Entry {
        uint32_t child;
        float tEntry;
    };
    Entry stack[kStackSize];
    int stackSize = 0;
    // Puts a child on the stack and brings it into the cache now, overlapping the memory
    // latency with the subtree visited first.
    auto push = [&](uint32_t child, float tEntry) {
        stack[stackSize++] = Entry{child, tEntry};
        if (!BVHReference::isLeaf(child)) {
            const char *address = reinterpret_cast<const char *>(&m_nodes[child]);
            for (size_t line = 0; line < sizeof(Node); line += 64)
                __builtin_prefetch(address + line);
        } else {
            prefetchLeaf(BVHReference::leafFirst(child), BVHReference::leafCount(child));
        }
    };
    uint32_t current = 0; // the root node
    bool hit = false;
    while (true) {
        if (!BVHReference::isLeaf(current)) {
            const Node &node = m_nodes[current];
            alignas(32) float distance[Width];
            unsigned entered = nodeRay.intersect(node, tMax, distance);
            if (entered != 0) {
                const int first = __builtin_ctz(entered);
                entered &= entered - 1;
                if (entered == 0) { // one child: no stack traffic
                    current = node.child[first];
                    continue;
                }
                if constexpr (AnyHit) {
                    // Stored order: the first child next, the others pushed last to first.
                    current = node.child[first];
                    while (entered != 0) {
                        const int i = 31 - __builtin_clz(entered);
                        entered &= ~(1u << i);
                        push(node.child[i], distance[i]);
                    }
                    continue;
                }
                const int second = __builtin_ctz(entered);
                entered &= entered - 1;
                if (entered == 0) { // two children: the nearer next, the farther pushed
                    const bool secondNearer = distance[second] < distance[first];
                    const int nearer = secondNearer ? second : first;
                    const int farther = secondNearer ? first : second;
                    push(node.child[farther], distance[farther]);
                    current = node.child[nearer];
                    continue;
                }
                // More: pushed sorted by entry distance, farthest deepest (an insertion sort
                // of at most Width), then the nearest popped.
                const int base = stackSize;
                auto insert = [&](int i) {
                    const Entry entry{node.child[i], distance[i]};
                    int position = stackSize++;
                    for (; position > base && stack[position - 1].tEntry < entry.tEntry; --position)
                        stack[position] = stack[position - 1];
                    stack[position] = entry;
                };
                insert(first);
                insert(second);
                while (entered != 0) {
                    insert(__builtin_ctz(entered));
                    entered &= entered - 1;
                }
                current = stack[--stackSize].child;
                const int pushed = stackSize;
                stackSize = base;
                for (int i = base; i < pushed; ++i)
                    push(stack[i].child, stack[i].tEntry);
                continue;
            }
        } else if (const uint32_t count = BVHReference::leafCount(current);
                   count > 0 && intersectLeaf(BVHReference::leafFirst(current), count, tMax)) {
            hit = true;
            if constexpr (AnyHit)
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

template <int Width> NodeRay<Width>::NodeRay(const Ray3f &ray) {
    // Per ray: for each axis, which of a node's two planes is entered first, the origin
    // and 1/d.
    for (int axis = 0; axis < 3; ++axis) {
        m_invDir[axis] = Simd::broadcast(ray.dRcp[axis]);
        m_origin[axis] = Simd::broadcast(ray.o[axis]);
        m_nearSide[axis] = ray.dRcp[axis] < 0.0f ? 1 : 0;
    }
    // A slab distance (plane − o)·(1/d) is within γ₃ of the exact one, relatively, so
    // widening the far distance by 2γ₃ keeps the test conservative under rounding (PBR 4th
    // ed. §6.8.2). The form plane·(1/d) − o·(1/d) would save a subtraction per ray, but
    // its error is absolute, as large as o/d's rounding, which no relative widening covers.
    m_farScale = Simd::broadcast(1.0f + 2.0f * gammaBound(3));
    m_segmentStart = Simd::broadcast(ray.mint);
}

template <int Width>
unsigned NodeRay<Width>::intersect(const BVHNode<Width> &node, float tMax, float *distance) const {
    // A zero direction component gives ±inf distances (NaN when the origin lies on the
    // plane): max and min return their second operand for a NaN, so such a plane leaves
    // the running interval as it was.
    unsigned entered = 0;
    for (int first = 0; first < Width; first += kLanes) {
        Lanes tNear = m_segmentStart, tFar = Simd::broadcast(tMax);
        for (int axis = 0; axis < 3; ++axis) {
            const Lanes nearPlane = Simd::load(&node.bounds[axis][m_nearSide[axis]][first]);
            const Lanes farPlane = Simd::load(&node.bounds[axis][1 - m_nearSide[axis]][first]);
            const Lanes t0 = Simd::mul(Simd::sub(nearPlane, m_origin[axis]), m_invDir[axis]);
            const Lanes t1 = Simd::mul(
                Simd::mul(Simd::sub(farPlane, m_origin[axis]), m_invDir[axis]), m_farScale);
            tNear = Simd::max(t0, tNear);
            tFar = Simd::min(t1, tFar);
        }
        Simd::store(distance + first, tNear);
        const int mask = Simd::lessEqual(tNear, tFar);
        entered |= static_cast<unsigned>(mask) << first;
    }
    return entered;
}

} // namespace nori
