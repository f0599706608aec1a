#include <nori/bvh.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <array>
#include <atomic>

namespace nori {

namespace {

/// A primitive during the build: its bounds, centroid and index.
struct PrimitiveRef {
    BoundingBox3f bounds;
    Point3f centroid;
    uint32_t index;
};

/// A node of the temporary tree; children index into the same array.
struct BuildNode {
    BoundingBox3f bounds;
    uint32_t children[2] = {0, 0};
    uint32_t first = 0, count = 0; ///< primitive range of the subtree
    uint16_t axis = 0;
    bool leaf = false;
};

struct Bin {
    BoundingBox3f bounds;
    BoundingBox3f centroidBounds;
    uint32_t count = 0;
};

/// Subtrees with more primitives than this are built as parallel tasks.
constexpr uint32_t kParallelThreshold = 4096;

class Builder {
public:
    Builder(std::vector<PrimitiveRef> &refs, float intersectionCost, uint32_t blockSize)
        : m_refs(refs), m_nodes(std::max<size_t>(1, 2 * refs.size())),
          m_intersectionCost(intersectionCost), m_blockSize(blockSize) {}

    /// Builds the subtree over refs[first, first + count), whose bounds and centroid
    /// bounds are given; returns its node index.
    uint32_t build(uint32_t first, uint32_t count, const BoundingBox3f &bounds,
                   const BoundingBox3f &centroidBounds, int depth) {
        const uint32_t nodeIndex = m_nextNode.fetch_add(1, std::memory_order_relaxed);
        BuildNode &node = m_nodes[nodeIndex];
        node.bounds = bounds;
        node.first = first;
        node.count = count;

        Split split;
        const bool found = depth < BVHBase::kSahDepthLimit
                               ? findSahSplit(first, count, bounds, centroidBounds, split)
                               : false;
        if (!found && count <= static_cast<uint32_t>(BVHBase::kMaxLeafSize)) {
            node.leaf = true;
            return nodeIndex;
        }

        uint32_t leftCount;
        BoundingBox3f leftBounds, rightBounds, leftCentroids, rightCentroids;
        if (found) {
            leftCount = partition(first, count, split);
            leftBounds = split.leftBounds;
            rightBounds = split.rightBounds;
            leftCentroids = split.leftCentroids;
            rightCentroids = split.rightCentroids;
            node.axis = static_cast<uint16_t>(split.axis);
        } else {
            // No useful SAH split (identical centroids, or too deep) but too many
            // primitives for a leaf: halve the list along the widest centroid axis.
            leftCount = count / 2;
            const int axis = widestAxis(centroidBounds);
            auto begin = m_refs.begin() + first;
            std::nth_element(begin, begin + leftCount, begin + count,
                             [axis](const PrimitiveRef &a, const PrimitiveRef &b) {
                                 return a.centroid[axis] < b.centroid[axis];
                             });
            node.axis = static_cast<uint16_t>(axis);
            rangeBounds(first, leftCount, leftBounds, leftCentroids);
            rangeBounds(first + leftCount, count - leftCount, rightBounds, rightCentroids);
        }

        uint32_t left = 0, right = 0;
        auto buildLeft = [&] {
            left = build(first, leftCount, leftBounds, leftCentroids, depth + 1);
        };
        auto buildRight = [&] {
            right =
                build(first + leftCount, count - leftCount, rightBounds, rightCentroids, depth + 1);
        };
        if (count > kParallelThreshold) {
            tbb::parallel_invoke(buildLeft, buildRight);
        } else {
            buildLeft();
            buildRight();
        }
        node.children[0] = left;
        node.children[1] = right;
        return nodeIndex;
    }

    const std::vector<BuildNode> &nodes() const { return m_nodes; }
    uint32_t nodeCount() const { return m_nextNode.load(); }

private:
    struct Split {
        int axis = -1;
        int bin = 0;         ///< primitives in bins [0, bin] go left
        float origin = 0.0f; ///< binning of the chosen axis: bin = scale·(c − origin)
        float scale = 0.0f;
        float cost = 0.0f;
        BoundingBox3f leftBounds, rightBounds, leftCentroids, rightCentroids;
    };

    static int widestAxis(const BoundingBox3f &box) {
        const Vector3f extents = box.getExtents();
        int axis = 0;
        extents.maxCoeff(&axis);
        return axis;
    }

    void rangeBounds(uint32_t first, uint32_t count, BoundingBox3f &bounds,
                     BoundingBox3f &centroids) const {
        bounds = BoundingBox3f();
        centroids = BoundingBox3f();
        for (uint32_t i = first; i < first + count; ++i) {
            bounds.expandBy(m_refs[i].bounds);
            centroids.expandBy(m_refs[i].centroid);
        }
    }

    /// Bins the centroids on every axis with a usable extent and sweeps the bin
    /// boundaries for the lowest SAH cost. Returns false when a leaf is cheaper.
    bool findSahSplit(uint32_t first, uint32_t count, const BoundingBox3f &bounds,
                      const BoundingBox3f &centroidBounds, Split &best) const {
        if (count <= 1)
            return false;
        const Vector3f extent = centroidBounds.getExtents();
        // Map a centroid to a bin: k·(c − min), with k slightly below kBinCount/extent so
        // that the maximum lands in the last bin.
        Vector3f scale;
        for (int axis = 0; axis < 3; ++axis)
            scale[axis] =
                extent[axis] > 0.0f ? BVHBase::kBinCount * (1.0f - 1e-6f) / extent[axis] : 0.0f;

        std::array<std::array<Bin, BVHBase::kBinCount>, 3> bins;
        for (uint32_t i = first; i < first + count; ++i) {
            const PrimitiveRef &ref = m_refs[i];
            for (int axis = 0; axis < 3; ++axis) {
                if (scale[axis] == 0.0f)
                    continue;
                const int b = binIndex(ref.centroid[axis], centroidBounds.min[axis], scale[axis]);
                Bin &bin = bins[axis][b];
                bin.bounds.expandBy(ref.bounds);
                bin.centroidBounds.expandBy(ref.centroid);
                ++bin.count;
            }
        }

        const float leafCost = m_intersectionCost * blocks(count);
        const float invArea = 1.0f / bounds.getSurfaceArea();
        best.cost = std::numeric_limits<float>::infinity();
        for (int axis = 0; axis < 3; ++axis) {
            if (scale[axis] == 0.0f)
                continue;
            // Sweep from the right: area and count of everything right of each boundary.
            std::array<float, BVHBase::kBinCount> rightArea{};
            std::array<uint32_t, BVHBase::kBinCount> rightCount{};
            BoundingBox3f accumulated;
            uint32_t accumulatedCount = 0;
            for (int b = BVHBase::kBinCount - 1; b > 0; --b) {
                accumulated.expandBy(bins[axis][b].bounds);
                accumulatedCount += bins[axis][b].count;
                rightArea[b] = accumulated.getSurfaceArea();
                rightCount[b] = accumulatedCount;
            }
            // Sweep from the left, splitting between bins b and b + 1.
            accumulated = BoundingBox3f();
            accumulatedCount = 0;
            for (int b = 0; b < BVHBase::kBinCount - 1; ++b) {
                accumulated.expandBy(bins[axis][b].bounds);
                accumulatedCount += bins[axis][b].count;
                if (accumulatedCount == 0 || rightCount[b + 1] == 0)
                    continue;
                const float cost = BVHBase::kTraversalCost +
                                   m_intersectionCost * invArea *
                                       (accumulated.getSurfaceArea() * blocks(accumulatedCount) +
                                        rightArea[b + 1] * blocks(rightCount[b + 1]));
                if (cost < best.cost) {
                    best.cost = cost;
                    best.axis = axis;
                    best.bin = b;
                }
            }
        }
        if (best.axis < 0)
            return false;
        if (best.cost >= leafCost && count <= static_cast<uint32_t>(BVHBase::kMaxLeafSize))
            return false;

        // The children's bounds follow from the bins.
        for (int b = 0; b < BVHBase::kBinCount; ++b) {
            const Bin &bin = bins[best.axis][b];
            if (bin.count == 0)
                continue;
            (b <= best.bin ? best.leftBounds : best.rightBounds).expandBy(bin.bounds);
            (b <= best.bin ? best.leftCentroids : best.rightCentroids).expandBy(bin.centroidBounds);
        }
        best.scale = scale[best.axis];
        best.origin = centroidBounds.min[best.axis];
        return true;
    }

    /// Primitives are tested a block (SIMD packet) at a time: n of them cost ⌈n/block⌉
    /// tests (the SAH with blocks, as in Embree's builders).
    float blocks(uint32_t count) const {
        const uint32_t blockCount = (count + m_blockSize - 1) / m_blockSize; // ⌈count/block⌉
        return static_cast<float>(blockCount);
    }

    static int binIndex(float centroid, float origin, float scale) {
        const int b = static_cast<int>(scale * (centroid - origin));
        return std::clamp(b, 0, BVHBase::kBinCount - 1);
    }

    /// Moves the primitives of bins [0, split.bin] to the front; returns their count.
    uint32_t partition(uint32_t first, uint32_t count, const Split &split) {
        auto begin = m_refs.begin() + first;
        auto middle = std::partition(begin, begin + count, [&](const PrimitiveRef &ref) {
            return binIndex(ref.centroid[split.axis], split.origin, split.scale) <= split.bin;
        });
        return static_cast<uint32_t>(middle - begin);
    }

    std::vector<PrimitiveRef> &m_refs;
    std::vector<BuildNode> m_nodes;
    std::atomic<uint32_t> m_nextNode{0};
    float m_intersectionCost;
    uint32_t m_blockSize;
};

} // namespace

template <int Width>
void BVH<Width>::build(const std::vector<BoundingBox3f> &bounds, float intersectionCost,
                       uint32_t leafAlignment) {
    m_nodes.clear();
    m_primitiveOrder.clear();
    m_bounds = BoundingBox3f();
    m_statistics = BVHBuildStatistics();

    // Primitives with empty or non-finite bounds (NaN vertices, ...) cannot be placed.
    std::vector<PrimitiveRef> refs;
    refs.reserve(bounds.size());
    for (uint32_t i = 0; i < bounds.size(); ++i) {
        const BoundingBox3f &box = bounds[i];
        if (!box.isValid() || !box.min.allFinite() || !box.max.allFinite()) {
            ++m_statistics.skippedPrimitives;
            continue;
        }
        refs.push_back({box, box.getCenter(), i});
    }
    m_statistics.primitives = refs.size();
    if (refs.empty())
        return;
    BoundingBox3f rootBounds, rootCentroids;
    for (const PrimitiveRef &ref : refs) {
        rootBounds.expandBy(ref.bounds);
        rootCentroids.expandBy(ref.centroid);
    }
    m_bounds = rootBounds;
    Builder builder(refs, intersectionCost, leafAlignment);
    builder.build(0, static_cast<uint32_t>(refs.size()), rootBounds, rootCentroids, 0);
    const std::vector<BuildNode> &buildNodes = builder.nodes();

    // Collapse the binary tree into wide nodes, depth-first: each wide node takes a
    // binary node's two children, then keeps opening the interior child of largest
    // area × primitives (its share of the SAH cost) until it has Width children. Opening by
    // area alone also opened small subtrees and left large ones as children, filling
    // 8-wide nodes less (3.9 children of 8 on nori-bench's mesh against 4.4). Children are
    // stored largest first, the order any-hit traversal visits them in.
    m_nodes.reserve(builder.nodeCount() / 2 + 1);
    const float rootArea = rootBounds.getSurfaceArea();
    auto relativeArea = [&](const BoundingBox3f &box) {
        return rootArea > 0.0f ? box.getSurfaceArea() / rootArea : 1.0f;
    };
    auto leafReference = [&](const BuildNode &leaf) {
        const size_t first =
            (m_primitiveOrder.size() + leafAlignment - 1) / leafAlignment * leafAlignment;
        // A leaf reference holds its first slot in 27 bits: 134M slots, padding included.
        if (first + leaf.count > static_cast<size_t>(BVHReference::kSlotMask) + 1)
            throw NoriException("{} primitives are more than one BVH holds: their leaves need "
                                "more than {} slots",
                                refs.size(), static_cast<size_t>(BVHReference::kSlotMask) + 1);
        m_primitiveOrder.resize(first, kNoPrimitive);
        for (uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i)
            m_primitiveOrder.push_back(refs[i].index);
        ++m_statistics.leaves;
        const uint32_t blockCount = (leaf.count + leafAlignment - 1) / leafAlignment;
        m_statistics.sahCost +=
            relativeArea(leaf.bounds) * intersectionCost * static_cast<float>(blockCount);
        return BVHReference::makeLeaf(static_cast<uint32_t>(first), leaf.count);
    };
    auto collapse = [&](auto &&self, uint32_t buildIndex, size_t depth) -> uint32_t {
        m_statistics.maxDepth = std::max(m_statistics.maxDepth, depth);
        std::array<uint32_t, Width> children{};
        int childCount = 0;
        const BuildNode &top = buildNodes[buildIndex];
        if (top.leaf) { // a root that is a leaf
            children[childCount++] = buildIndex;
        } else {
            children[childCount++] = top.children[0];
            children[childCount++] = top.children[1];
        }
        auto area = [&](uint32_t index) { return buildNodes[index].bounds.getSurfaceArea(); };
        // A subtree's share of the SAH cost: how often rays enter it times what it holds.
        auto cost = [&](uint32_t index) {
            return area(index) * static_cast<float>(buildNodes[index].count);
        };
        while (childCount < Width) {
            int costliest = -1;
            for (int i = 0; i < childCount; ++i)
                if (!buildNodes[children[i]].leaf &&
                    (costliest < 0 || cost(children[i]) > cost(children[costliest])))
                    costliest = i;
            if (costliest < 0)
                break;
            const BuildNode &opened = buildNodes[children[costliest]];
            children[costliest] = opened.children[0];
            children[childCount++] = opened.children[1];
        }
        std::stable_sort(children.begin(), children.begin() + childCount,
                         [&](uint32_t a, uint32_t b) { return area(a) > area(b); });

        const auto nodeIndex = static_cast<uint32_t>(m_nodes.size());
        m_nodes.emplace_back();
        m_statistics.sahCost += relativeArea(top.bounds) * kTraversalCost;
        for (int i = 0; i < Width; ++i) {
            BoundingBox3f box; // empty: min +inf, max -inf
            uint32_t reference = BVHReference::makeLeaf(0, 0);
            if (i < childCount) {
                const BuildNode &child = buildNodes[children[i]];
                box = child.bounds;
                reference = child.leaf ? leafReference(child) : self(self, children[i], depth + 1);
            }
            Node &node = m_nodes[nodeIndex]; // after the recursion, which may reallocate
            for (int axis = 0; axis < 3; ++axis) {
                node.bounds[axis][0][i] = box.min[axis];
                node.bounds[axis][1][i] = box.max[axis];
            }
            node.child[i] = reference;
        }
        return nodeIndex;
    };
    collapse(collapse, 0, 1);
    m_nodes.shrink_to_fit();
    m_primitiveOrder.shrink_to_fit();
    m_statistics.nodes = m_nodes.size();
}

template class BVH<4>;
template class BVH<8>;

} // namespace nori
