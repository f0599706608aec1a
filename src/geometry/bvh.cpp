#include <nori/bvh.h>
#include <nori/parallel.h>

#include <array>
#include <atomic>
#include <cstring>
#include <memory>

namespace nori {

namespace {

/// A box in two SSE registers, for the build's inner loops: lanes 0-2 hold x, y, z;
/// lane 3 is ignored.
struct SimdBox {
    __m128 lower = _mm_set1_ps(kInfinity);
    __m128 upper = _mm_set1_ps(-kInfinity);

    void expand(__m128 boxLower, __m128 boxUpper) {
        lower = _mm_min_ps(lower, boxLower);
        upper = _mm_max_ps(upper, boxUpper);
    }
    void expand(const SimdBox &box) { expand(box.lower, box.upper); }
    void expand(__m128 point) { expand(point, point); }

    BoundingBox3f box() const {
        alignas(16) float low[4], high[4];
        _mm_store_ps(low, lower);
        _mm_store_ps(high, upper);
        return BoundingBox3f(Point3f(low[0], low[1], low[2]), Point3f(high[0], high[1], high[2]));
    }
};

/// A primitive during the build, 32 bytes: its box, with its index in the fourth lane
/// of the minimum (as bits; box operations ignore that lane).
struct PrimitiveRef {
    __m128 lower, upper;

    PrimitiveRef() = default;
    PrimitiveRef(const BoundingBox3f &box, uint32_t index)
        : lower(_mm_castsi128_ps(_mm_setr_epi32(bitCast(box.min.x()), bitCast(box.min.y()),
                                                bitCast(box.min.z()), static_cast<int>(index)))),
          upper(_mm_setr_ps(box.max.x(), box.max.y(), box.max.z(), 0.0f)) {}

    /// Twice the box's centroid: the build bins centroids in that scale, one addition.
    __m128 centroid2() const { return _mm_add_ps(lower, upper); }
    uint32_t index() const {
        return static_cast<uint32_t>(
            _mm_cvtsi128_si32(_mm_shuffle_epi32(_mm_castps_si128(lower), 3)));
    }

private:
    static int bitCast(float value) {
        int bits;
        std::memcpy(&bits, &value, sizeof(bits));
        return bits;
    }
};

/// The build's primitives: tens of megabytes, filled in parallel (see LargeArrayAllocator).
using PrimitiveRefs = std::vector<PrimitiveRef, LargeArrayAllocator<PrimitiveRef>>;

/// A node of the temporary binary tree; children index into the same array. Trivial, so
/// that the array sized for the worst case (2n − 1 nodes) costs only the pages used.
struct BuildNode {
    float lower[3], upper[3]; ///< bounds
    uint32_t children[2];
    uint32_t first, count; ///< primitive range of the subtree
    bool leaf;

    void setBounds(const SimdBox &box) {
        const BoundingBox3f bounds = box.box();
        for (int axis = 0; axis < 3; ++axis) {
            lower[axis] = bounds.min[axis];
            upper[axis] = bounds.max[axis];
        }
    }
    BoundingBox3f bounds() const {
        return BoundingBox3f(Point3f(lower[0], lower[1], lower[2]),
                             Point3f(upper[0], upper[1], upper[2]));
    }
};

/// Maps doubled centroids to bins on the three axes at once: ⌊scale·(c − origin)⌋,
/// clamped to [0, binCount − 1] (clamping before truncation gives the same bin).
struct BinMapping {
    __m128 origin, scale;
    int binCount;

    /// `binCount` bins on each axis over the centroids' bounds.
    BinMapping(const SimdBox &centroids, int binCount)
        : origin(centroids.lower), binCount(binCount) {
        // k slightly below binCount/extent, so that the maximum lands in the last bin; an
        // axis without extent gets k = 0 and is not split.
        alignas(16) float extent[4], k[4] = {0, 0, 0, 0};
        _mm_store_ps(extent, _mm_sub_ps(centroids.upper, centroids.lower));
        for (int axis = 0; axis < 3; ++axis)
            k[axis] = extent[axis] > 0.0f
                          ? static_cast<float>(binCount) * (1.0f - 1e-6f) / extent[axis]
                          : 0.0f;
        scale = _mm_load_ps(k);
    }
    bool splits(int axis) const {
        alignas(16) float k[4];
        _mm_store_ps(k, scale);
        return k[axis] > 0.0f;
    }
    /// The bin coordinates, still as floats: their integer parts are the bins.
    __m128 coordinates(__m128 centroid2) const {
        const __m128 x = _mm_mul_ps(_mm_sub_ps(centroid2, origin), scale);
        return _mm_min_ps(_mm_max_ps(x, _mm_setzero_ps()),
                          _mm_set1_ps(static_cast<float>(binCount - 1)));
    }
};

/// Three boxes transposed: lane a of lower[k] is box a's minimum on axis k. The SAH sweep
/// advances the three binning axes at once this way.
struct TransposedBoxes {
    __m128 lower[3], upper[3];

    TransposedBoxes() {
        for (int k = 0; k < 3; ++k) {
            lower[k] = _mm_set1_ps(kInfinity);
            upper[k] = _mm_set1_ps(-kInfinity);
        }
    }
    TransposedBoxes(const SimdBox &a, const SimdBox &b, const SimdBox &c) {
        __m128 low3 = _mm_setzero_ps(), high3 = _mm_setzero_ps();
        lower[0] = a.lower, lower[1] = b.lower, lower[2] = c.lower;
        upper[0] = a.upper, upper[1] = b.upper, upper[2] = c.upper;
        _MM_TRANSPOSE4_PS(lower[0], lower[1], lower[2], low3);
        _MM_TRANSPOSE4_PS(upper[0], upper[1], upper[2], high3);
    }
    void expand(const TransposedBoxes &other) {
        for (int k = 0; k < 3; ++k) {
            lower[k] = _mm_min_ps(lower[k], other.lower[k]);
            upper[k] = _mm_max_ps(upper[k], other.upper[k]);
        }
    }
    /// The three surface areas, each as BoundingBox3f::getSurfaceArea computes it.
    __m128 surfaceAreas() const {
        const __m128 ex = _mm_sub_ps(upper[0], lower[0]), ey = _mm_sub_ps(upper[1], lower[1]),
                     ez = _mm_sub_ps(upper[2], lower[2]);
        const __m128 sum =
            _mm_add_ps(_mm_add_ps(_mm_mul_ps(ex, ey), _mm_mul_ps(ey, ez)), _mm_mul_ps(ez, ex));
        return _mm_mul_ps(_mm_set1_ps(2.0f), sum);
    }
};

/// The bins of the three axes: the union of their primitives' boxes, and their counts.
struct Bins {
    /// From this many primitives on, binning uses two sets of bins (see add()).
    static constexpr ptrdiff_t kTwoSetMinimum = 64;

    std::array<std::array<SimdBox, BVHBase::kBinCount>, 3> boxes;
    /// counts[b][axis]: four lanes per bin (the fourth unused), read as one vector.
    alignas(16) std::array<std::array<uint32_t, 4>, BVHBase::kBinCount> counts{};

    void add(const PrimitiveRef &ref, const BinMapping &mapping) {
        alignas(16) int bin[4];
        _mm_store_si128(reinterpret_cast<__m128i *>(bin),
                        _mm_cvttps_epi32(mapping.coordinates(ref.centroid2())));
        for (int axis = 0; axis < 3; ++axis) {
            boxes[axis][bin[axis]].expand(ref.lower, ref.upper);
            ++counts[bin[axis]][axis];
        }
    }
    void add(const PrimitiveRef *begin, const PrimitiveRef *end, const BinMapping &mapping) {
        // Neighbouring primitives often share a bin, and each update waits for the last
        // one's store: over many primitives, odd ones go to a second set of bins, so two
        // chains of updates run side by side.
        if (end - begin < kTwoSetMinimum) {
            for (const PrimitiveRef *ref = begin; ref != end; ++ref)
                add(*ref, mapping);
            return;
        }
        Bins odd;
        const PrimitiveRef *ref = begin;
        for (; ref + 1 < end; ref += 2) {
            add(ref[0], mapping);
            odd.add(ref[1], mapping);
        }
        if (ref != end)
            add(*ref, mapping);
        add(odd);
    }
    void add(const Bins &other) {
        for (int axis = 0; axis < 3; ++axis)
            for (int b = 0; b < BVHBase::kBinCount; ++b) {
                boxes[axis][b].expand(other.boxes[axis][b]);
                counts[b][axis] += other.counts[b][axis];
            }
    }
};

/// Subtrees with more primitives than this are built as parallel tasks.
constexpr uint32_t kParallelThreshold = 4096;
/// Nodes with more primitives than this are binned in parallel.
constexpr uint32_t kParallelBinThreshold = 65536;

class Builder {
public:
    Builder(PrimitiveRefs &refs, float intersectionCost, uint32_t blockSize, float rootArea)
        : m_refs(refs),
          // At most 2n − 1 nodes. Default-initialised: BuildNode is trivial, so no page is
          // touched before use (make_unique would zero them all).
          m_nodes(new BuildNode[std::max<size_t>(1, 2 * refs.size())]), // NOLINT
          m_intersectionCost(intersectionCost), m_blockSize(blockSize), m_rootArea(rootArea) {}

    /// Builds the subtree over refs[first, first + count), whose bounds and doubled
    /// centroid bounds are given; returns its node index.
    uint32_t build(uint32_t first, uint32_t count, const SimdBox &bounds, const SimdBox &centroids,
                   int depth) {
        const uint32_t nodeIndex = m_nextNode.fetch_add(1, std::memory_order_relaxed);
        BuildNode &node = m_nodes[nodeIndex];
        node.setBounds(bounds);
        node.first = first;
        node.count = count;
        node.leaf = false;
        const BinMapping mapping(centroids, binCount(bounds, count));
        Split split;
        const bool found = depth < BVHBase::kSahDepthLimit
                               ? findSahSplit(first, count, bounds, mapping, split)
                               : false;
        if (!found && count <= static_cast<uint32_t>(BVHBase::kMaxLeafSize)) {
            node.leaf = true;
            m_leafCount.fetch_add(1, std::memory_order_relaxed);
            return nodeIndex;
        }

        uint32_t leftCount;
        SimdBox leftBounds, rightBounds, leftCentroids, rightCentroids;
        if (found) {
            leftCount = partition(first, count, split, mapping, leftCentroids, rightCentroids);
            leftBounds = split.leftBounds;
            rightBounds = split.rightBounds;
        } else {
            // No useful SAH split (identical centroids, or too deep) but too many
            // primitives for a leaf: halve the list along the widest centroid axis.
            leftCount = count / 2;
            const int axis = widestAxis(centroids);
            auto begin = m_refs.begin() + first;
            std::nth_element(begin, begin + leftCount, begin + count,
                             [axis](const PrimitiveRef &a, const PrimitiveRef &b) {
                                 return lane(a.centroid2(), axis) < lane(b.centroid2(), axis);
                             });
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
            parallelInvoke(buildLeft, buildRight);
        } else {
            buildLeft();
            buildRight();
        }
        node.children[0] = left;
        node.children[1] = right;
        return nodeIndex;
    }

    /// Primitives are tested a block (SIMD packet) at a time: n of them cost ⌈n/block⌉
    /// tests (the SAH with blocks, as in Embree's builders).
    float blocks(uint32_t count) const {
        const uint32_t blockCount = (count + m_blockSize - 1) / m_blockSize; // ⌈count/block⌉
        return static_cast<float>(blockCount);
    }
    /// A primitive test's cost, in units of a box test.
    float intersectionCost() const { return m_intersectionCost; }
    const BuildNode &node(uint32_t index) const { return m_nodes[index]; }
    uint32_t nodeCount() const { return m_nextNode.load(); }
    uint32_t leafCount() const { return m_leafCount.load(); }

private:
    struct Split {
        int axis = -1;
        int bin = 0; ///< primitives in bins [0, bin] go left
        float cost = 0.0f;
        SimdBox leftBounds, rightBounds;
    };

    /// Bins for a node of `count` primitives. A small node far down a large tree bins into
    /// 4 + n/20 (as Embree's builders do), since the sweep over the bins would cost more
    /// than binning its few primitives; but a split's share of the tree's cost is the
    /// node's share of the root's area, so a node of more than 1/1024 of it (the top of a
    /// tree, and every node of a small scene such as a Cornell box) keeps every bin.
    int binCount(const SimdBox &bounds, uint32_t count) const {
        constexpr float kCoarseBinningArea = 1.0f / 1024.0f;
        if (bounds.box().getSurfaceArea() > kCoarseBinningArea * m_rootArea)
            return BVHBase::kBinCount;
        return static_cast<int>(std::min<uint32_t>(BVHBase::kBinCount, 4 + count / 20));
    }

    static float lane(__m128 value, int index) {
        alignas(16) float lanes[4];
        _mm_store_ps(lanes, value);
        return lanes[index];
    }

    static int widestAxis(const SimdBox &box) {
        const Vector3f extents = box.box().getExtents();
        int axis = 0;
        extents.maxCoeff(&axis);
        return axis;
    }

    void rangeBounds(uint32_t first, uint32_t count, SimdBox &bounds, SimdBox &centroids) const {
        bounds = centroids = SimdBox();
        for (uint32_t i = first; i < first + count; ++i) {
            bounds.expand(m_refs[i].lower, m_refs[i].upper);
            centroids.expand(m_refs[i].centroid2());
        }
    }

    /// Bins the centroids on every axis with a usable extent and sweeps the bin
    /// boundaries for the lowest SAH cost. Returns false when a leaf is cheaper.
    bool findSahSplit(uint32_t first, uint32_t count, const SimdBox &bounds,
                      const BinMapping &mapping, Split &best) const {
        // The binary tree goes down to one block (CollapseCosts merges blocks into larger
        // leaves). A split costs at least a traversal step, so a block that costs no more
        // stays a leaf.
        const float leafCost = m_intersectionCost * blocks(count);
        if (count <= 1 || (count <= m_blockSize && leafCost <= BVHBase::kTraversalCost))
            return false;
        const PrimitiveRef *begin = m_refs.data() + first, *end = begin + count;
        Bins bins;
        if (count > kParallelBinThreshold) {
            bins = parallelReduce(
                begin, end, kParallelBinThreshold / 4, Bins(),
                [&](const PrimitiveRef *from, const PrimitiveRef *to, Bins partial) {
                    partial.add(from, to, mapping);
                    return partial;
                },
                [](Bins a, const Bins &b) {
                    a.add(b);
                    return a;
                });
        } else {
            bins.add(begin, end, mapping);
        }

        const float invArea = 1.0f / bounds.box().getSurfaceArea();
        // The sweeps run on the three axes at once, lane a for axis a.
        constexpr int kBins = BVHBase::kBinCount;
        auto countsOf = [&](int b) {
            return _mm_load_si128(reinterpret_cast<const __m128i *>(bins.counts[b].data()));
        };
        TransposedBoxes binBoxes[kBins];
        const int binCount = mapping.binCount;
        for (int b = 0; b < binCount; ++b)
            binBoxes[b] = TransposedBoxes(bins.boxes[0][b], bins.boxes[1][b], bins.boxes[2][b]);
        // From the right: area and count of everything right of each boundary.
        __m128 rightArea[kBins];
        __m128i rightCount[kBins];
        TransposedBoxes accumulated;
        __m128i accumulatedCount = _mm_setzero_si128();
        for (int b = binCount - 1; b > 0; --b) {
            accumulated.expand(binBoxes[b]);
            accumulatedCount = _mm_add_epi32(accumulatedCount, countsOf(b));
            rightArea[b] = accumulated.surfaceAreas();
            rightCount[b] = accumulatedCount;
        }
        // From the left, splitting between bins b and b + 1: cost[b][axis].
        alignas(16) std::array<std::array<float, 4>, kBins> cost;
        const __m128 costScale = _mm_set1_ps(m_intersectionCost * invArea);
        const __m128i empty = _mm_setzero_si128();
        accumulated = TransposedBoxes();
        accumulatedCount = _mm_setzero_si128();
        for (int b = 0; b < binCount - 1; ++b) {
            accumulated.expand(binBoxes[b]);
            accumulatedCount = _mm_add_epi32(accumulatedCount, countsOf(b));
            const __m128 sides =
                _mm_add_ps(_mm_mul_ps(accumulated.surfaceAreas(), blocks(accumulatedCount)),
                           _mm_mul_ps(rightArea[b + 1], blocks(rightCount[b + 1])));
            const __m128 splitCost =
                _mm_add_ps(_mm_set1_ps(BVHBase::kTraversalCost), _mm_mul_ps(costScale, sides));
            // A boundary with nothing on one side is no split.
            const __m128 oneSided =
                _mm_castsi128_ps(_mm_or_si128(_mm_cmpeq_epi32(accumulatedCount, empty),
                                              _mm_cmpeq_epi32(rightCount[b + 1], empty)));
            _mm_store_ps(cost[b].data(), _mm_or_ps(_mm_andnot_ps(oneSided, splitCost),
                                                   _mm_and_ps(oneSided, _mm_set1_ps(kInfinity))));
        }
        best.cost = kInfinity;
        for (int axis = 0; axis < 3; ++axis) {
            if (!mapping.splits(axis))
                continue;
            for (int b = 0; b < binCount - 1; ++b)
                if (cost[b][axis] < best.cost) {
                    best.cost = cost[b][axis];
                    best.axis = axis;
                    best.bin = b;
                }
        }
        if (best.axis < 0)
            return false;
        if (best.cost >= leafCost && count <= m_blockSize)
            return false;

        // The children's bounds follow from the bins.
        for (int b = 0; b < binCount; ++b)
            (b <= best.bin ? best.leftBounds : best.rightBounds).expand(bins.boxes[best.axis][b]);
        return true;
    }

    /// blocks() of four counts: ⌈n/block⌉ as the truncated quotient of (n + block − 1)/block,
    /// exact since counts are far below 2^24 and a non-integer quotient is at least 1/block
    /// above its floor.
    __m128 blocks(__m128i counts) const {
        const __m128 block = _mm_set1_ps(static_cast<float>(m_blockSize));
        const __m128 padded =
            _mm_add_ps(_mm_cvtepi32_ps(counts), _mm_set1_ps(static_cast<float>(m_blockSize - 1)));
        return _mm_cvtepi32_ps(_mm_cvttps_epi32(_mm_div_ps(padded, block)));
    }

    /// Moves the primitives of bins [0, split.bin] to the front and returns their count;
    /// on the way, bounds the doubled centroids of each side.
    uint32_t partition(uint32_t first, uint32_t count, const Split &split,
                       const BinMapping &mapping, SimdBox &leftCentroids, SimdBox &rightCentroids) {
        // Bin ⌊x⌋ <= b exactly when x < b + 1.
        const __m128 limit = _mm_set1_ps(static_cast<float>(split.bin + 1));
        const int axisBit = 1 << split.axis;
        auto goesLeft = [&](__m128 centroid2) {
            return (_mm_movemask_ps(_mm_cmplt_ps(mapping.coordinates(centroid2), limit)) &
                    axisBit) != 0;
        };
        // Branch-free (Lomuto's scheme): every primitive is swapped with the first one
        // not yet known to go left, and that boundary moves on past a left primitive. The
        // sides are about equally likely, so a branch on them would be mispredicted often.
        PrimitiveRef *const begin = m_refs.data() + first, *const end = begin + count;
        PrimitiveRef *boundary = begin;
        for (PrimitiveRef *ref = begin; ref != end; ++ref) {
            const PrimitiveRef moved = *ref;
            const bool left = goesLeft(moved.centroid2());
            *ref = *boundary;
            *boundary = moved;
            boundary += left ? 1 : 0;
        }
        for (const PrimitiveRef *ref = begin; ref != boundary; ++ref)
            leftCentroids.expand(ref->centroid2());
        for (const PrimitiveRef *ref = boundary; ref != end; ++ref)
            rightCentroids.expand(ref->centroid2());
        return static_cast<uint32_t>(boundary - begin);
    }

    PrimitiveRefs &m_refs;
    std::unique_ptr<BuildNode[]> m_nodes;
    std::atomic<uint32_t> m_nextNode{0}, m_leafCount{0};
    float m_intersectionCost;
    uint32_t m_blockSize;
    float m_rootArea;
};

/// The SAH-optimal collapse of a binary tree into nodes of Width children (Ylitie, Karras
/// and Laine, "Efficient Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs",
/// HPG 2017, §3.1). cost(n, i) is the least SAH cost of binary node n's subtree as at most
/// i children of a wide node: n itself (a leaf, or a wide node whose children cost
/// cost(left, k) + cost(right, Width − k) at best), or cost(left, k) + cost(right, i − k)
/// with n's slots split between its children. A post-order pass fills the table, large
/// subtrees in parallel.
template <int Width> class CollapseCosts {
public:
    explicit CollapseCosts(const Builder &builder)
        // Default-initialised: every entry is written once, by the thread that owns its
        // subtree, so no serial pass first zeroes (and faults in) the whole table.
        : m_builder(builder) {
        m_entries.resize(builder.nodeCount());
        if (builder.nodeCount() > 0)
            fill(0);
    }

    /// Whether binary node `index`, as a child of a wide node, is a leaf.
    bool isLeaf(uint32_t index) const { return m_entries[index].leaf; }

    /// The children of the wide node made of binary node `index` (not a leaf): their
    /// count, and their binary nodes in `children`.
    int children(uint32_t index, std::array<uint32_t, Width> &children) const {
        int count = 0;
        if (m_builder.node(index).leaf) { // a root that is a leaf
            children[count++] = index;
            return count;
        }
        gather(index, Width, true, children, count);
        return count;
    }

private:
    struct Entry {
        std::array<float, Width> cost;        ///< cost[i − 1]: cost(n, i)
        std::array<uint8_t, Width> leftSlots; ///< [i − 1]: the left child's slots in the best
                                              ///< split of i
        uint8_t splits; ///< bit i − 1: with i slots, splitting beats n itself
        bool leaf;      ///< n by itself is a leaf
    };

    /// Fills the entries of binary node `index`'s subtree, children first.
    void fill(uint32_t index) {
        const BuildNode &node = m_builder.node(index);
        Entry &entry = m_entries[index];
        const float area = node.bounds().getSurfaceArea();
        const float leafCost =
            node.count <= static_cast<uint32_t>(BVHBase::kMaxLeafSize)
                ? area * m_builder.intersectionCost() * m_builder.blocks(node.count)
                : kInfinity;
        if (node.leaf) {
            entry.leaf = true;
            entry.cost.fill(leafCost);
            entry.splits = 0;
            return;
        }
        if (node.count > kParallelThreshold)
            parallelInvoke([&] { fill(node.children[0]); }, [&] { fill(node.children[1]); });
        else
            fill(node.children[0]), fill(node.children[1]);
        const Entry &left = m_entries[node.children[0]], &right = m_entries[node.children[1]];
        std::array<float, Width + 1> split{}; // split[i]: the best split of i slots
        for (int slots = 2; slots <= Width; ++slots) {
            split[slots] = kInfinity;
            for (int k = 1; k < slots; ++k) {
                const float cost = left.cost[k - 1] + right.cost[slots - k - 1];
                if (cost < split[slots]) {
                    split[slots] = cost;
                    entry.leftSlots[slots - 1] = static_cast<uint8_t>(k);
                }
            }
        }
        const float nodeCost = area * BVHBase::kTraversalCost + split[Width];
        entry.leaf = leafCost <= nodeCost;
        entry.cost[0] = std::min(leafCost, nodeCost);
        entry.splits = 0;
        for (int slots = 2; slots <= Width; ++slots) {
            if (split[slots] < entry.cost[0])
                entry.splits |= static_cast<uint8_t>(1u << (slots - 1));
            entry.cost[slots - 1] = std::min(entry.cost[0], split[slots]);
        }
    }

    /// Appends the children that binary node `index` becomes with `slots` slots; `open`:
    /// split it whatever it costs (it is the wide node being made).
    void gather(uint32_t index, int slots, bool open, std::array<uint32_t, Width> &children,
                int &count) const {
        const Entry &entry = m_entries[index];
        if (!open && ((entry.splits >> (slots - 1)) & 1) == 0) {
            children[count++] = index;
            return;
        }
        const BuildNode &node = m_builder.node(index);
        const int leftSlots = entry.leftSlots[slots - 1];
        gather(node.children[0], leftSlots, false, children, count);
        gather(node.children[1], slots - leftSlots, false, children, count);
    }

    const Builder &m_builder;
    /// Filled in parallel (see LargeArrayAllocator).
    std::vector<Entry, LargeArrayAllocator<Entry>> m_entries;
};

/// Writes the wide tree that CollapseCosts chooses: nodes in depth-first order, each
/// node's children largest box first (the order any-hit traversal visits them in), its
/// leaves before its subtrees, so that the leaves a ray enters together lie side by side
/// in leaf order. Two parallel passes: the first sizes every wide subtree (nodes and leaf
/// slots), so that the second can write each subtree into its own ranges of the arrays.
template <int Width> class WideTreeWriter {
public:
    using Node = BVHNode<Width>;

    /// What a wide subtree holds, and its share of the tree's statistics.
    struct Subtree {
        uint32_t nodes = 0;
        size_t slots = 0; ///< leaf slots, each leaf padded to the alignment
        size_t leaves = 0;
        size_t depth = 0;
        double sahCost = 0.0; ///< relative to the root's area
    };

    WideTreeWriter(const Builder &builder, const CollapseCosts<Width> &costs,
                   const PrimitiveRefs &refs, uint32_t leafAlignment)
        : m_builder(builder), m_costs(costs), m_refs(refs), m_leafAlignment(leafAlignment),
          m_rootArea(area(0)),
          // Written only where a wide node is made, by the thread making it.
          m_subtreeNodes(new uint32_t[builder.nodeCount()]), // NOLINT
          m_subtreeSlots(new size_t[builder.nodeCount()]) {} // NOLINT

    /// Pass 1: sizes the wide subtree made of binary node `index` and of every wide
    /// subtree below it.
    Subtree measure(uint32_t index) {
        std::array<uint32_t, Width> children{};
        const int childCount = sortedChildren(index, children);
        Subtree result;
        result.nodes = 1;
        result.sahCost = relativeArea(index) * BVHBase::kTraversalCost;
        std::array<Subtree, Width> below{};
        forEachChild(index, childCount, [&](int i) {
            if (!m_costs.isLeaf(children[i]))
                below[i] = measure(children[i]);
        });
        for (int i = 0; i < childCount; ++i) {
            if (m_costs.isLeaf(children[i])) {
                const BuildNode &leaf = m_builder.node(children[i]);
                result.slots += paddedSlots(leaf.count);
                result.leaves += 1;
                result.sahCost += relativeArea(children[i]) * m_builder.intersectionCost() *
                                  m_builder.blocks(leaf.count);
                continue;
            }
            result.nodes += below[i].nodes;
            result.slots += below[i].slots;
            result.leaves += below[i].leaves;
            result.depth = std::max(result.depth, below[i].depth);
            result.sahCost += below[i].sahCost;
        }
        result.depth += 1;
        m_subtreeNodes[index] = result.nodes;
        m_subtreeSlots[index] = result.slots;
        return result;
    }

    /// Pass 2: writes the wide node made of binary node `index` at nodes[nodeIndex], its
    /// leaves' primitives from slot `firstSlot` on, and its subtrees after them.
    void write(uint32_t index, uint32_t nodeIndex, size_t firstSlot, Node *nodes,
               uint32_t *primitiveOrder) const {
        std::array<uint32_t, Width> children{};
        const int childCount = sortedChildren(index, children);
        Node &node = nodes[nodeIndex];
        std::fill(std::begin(node.padding), std::end(node.padding), uint8_t(0));
        auto setChild = [&](int i, const BoundingBox3f &box, uint32_t reference) {
            for (int axis = 0; axis < 3; ++axis) {
                node.bounds[axis][0][i] = box.min[axis];
                node.bounds[axis][1][i] = box.max[axis];
            }
            node.child[i] = reference;
        };
        size_t nextSlot = firstSlot;
        for (int i = 0; i < childCount; ++i) {
            if (!m_costs.isLeaf(children[i]))
                continue;
            const BuildNode &leaf = m_builder.node(children[i]);
            for (uint32_t k = 0; k < paddedSlots(leaf.count); ++k)
                primitiveOrder[nextSlot + k] =
                    k < leaf.count ? m_refs[leaf.first + k].index() : BVHBase::kNoPrimitive;
            setChild(i, leaf.bounds(),
                     BVHReference::makeLeaf(static_cast<uint32_t>(nextSlot), leaf.count));
            nextSlot += paddedSlots(leaf.count);
        }
        for (int i = childCount; i < Width; ++i) // unused: an empty box, which no ray enters
            setChild(i, BoundingBox3f(), BVHReference::makeLeaf(0, 0));
        std::array<uint32_t, Width> childNode{};
        std::array<size_t, Width> childSlot{};
        uint32_t nextNode = nodeIndex + 1;
        for (int i = 0; i < childCount; ++i) {
            if (m_costs.isLeaf(children[i]))
                continue;
            childNode[i] = nextNode;
            childSlot[i] = nextSlot;
            setChild(i, m_builder.node(children[i]).bounds(), nextNode);
            nextNode += m_subtreeNodes[children[i]];
            nextSlot += m_subtreeSlots[children[i]];
        }
        forEachChild(index, childCount, [&](int i) {
            if (!m_costs.isLeaf(children[i]))
                write(children[i], childNode[i], childSlot[i], nodes, primitiveOrder);
        });
    }

private:
    float area(uint32_t index) const { return m_builder.node(index).bounds().getSurfaceArea(); }
    /// A node's share of the root's area: the probability that a ray through the root
    /// meets it (1 when the root has no area).
    double relativeArea(uint32_t index) const {
        return m_rootArea > 0.0f ? static_cast<double>(area(index)) / m_rootArea : 1.0;
    }

    size_t paddedSlots(uint32_t count) const {
        const size_t blocks = (count + m_leafAlignment - 1) / m_leafAlignment;
        return blocks * m_leafAlignment;
    }

    /// The wide node's children, largest area first (ties in the order gathered): an
    /// insertion sort, as there are at most Width.
    int sortedChildren(uint32_t index, std::array<uint32_t, Width> &children) const {
        const int childCount = m_costs.children(index, children);
        std::array<float, Width> areas{};
        for (int i = 0; i < childCount; ++i) {
            const uint32_t child = children[i];
            const float childArea = area(child);
            int position = i;
            for (; position > 0 && areas[position - 1] < childArea; --position) {
                areas[position] = areas[position - 1];
                children[position] = children[position - 1];
            }
            areas[position] = childArea;
            children[position] = child;
        }
        return childCount;
    }

    /// Runs visit(i) for each child, in parallel below a node with many primitives.
    template <typename Visit>
    void forEachChild(uint32_t index, int childCount, Visit &&visit) const {
        if (m_builder.node(index).count > kParallelThreshold)
            parallelFor(0, childCount, [&](int i) { visit(i); });
        else
            for (int i = 0; i < childCount; ++i)
                visit(i);
    }

    const Builder &m_builder;
    const CollapseCosts<Width> &m_costs;
    const PrimitiveRefs &m_refs;
    uint32_t m_leafAlignment;
    float m_rootArea;
    /// Per binary node that becomes a wide node: its subtree's nodes and slots.
    std::unique_ptr<uint32_t[]> m_subtreeNodes;
    std::unique_ptr<size_t[]> m_subtreeSlots;
};

} // namespace

template <int Width>
void BVH<Width>::build(size_t count, const std::function<BoundingBox3f(size_t)> &boundsOf,
                       float intersectionCost, uint32_t leafAlignment) {
    m_nodes.clear();
    m_primitiveOrder.clear();
    m_bounds = BoundingBox3f();
    m_statistics = BVHBuildStatistics();

    // The references and the root's bounds, in parallel. Primitives with empty or
    // non-finite bounds (NaN vertices, ...) cannot be placed: they are marked, then dropped.
    PrimitiveRefs refs(count);
    struct RootBounds {
        SimdBox bounds, centroids;
        size_t skipped = 0;
    };
    const RootBounds root = parallelReduce(
        size_t(0), count, 16384, RootBounds(),
        [&](size_t first, size_t last, RootBounds partial) {
            for (size_t i = first; i != last; ++i) {
                const BoundingBox3f box = boundsOf(i);
                if (!box.isValid() || !box.min.allFinite() || !box.max.allFinite()) {
                    refs[i] = PrimitiveRef(BoundingBox3f(), kNoPrimitive);
                    ++partial.skipped;
                    continue;
                }
                refs[i] = PrimitiveRef(box, static_cast<uint32_t>(i));
                partial.bounds.expand(refs[i].lower, refs[i].upper);
                partial.centroids.expand(refs[i].centroid2());
            }
            return partial;
        },
        [](RootBounds a, const RootBounds &b) {
            a.bounds.expand(b.bounds);
            a.centroids.expand(b.centroids);
            a.skipped += b.skipped;
            return a;
        });
    if (root.skipped > 0)
        refs.erase(
            std::remove_if(refs.begin(), refs.end(),
                           [](const PrimitiveRef &ref) { return ref.index() == kNoPrimitive; }),
            refs.end());
    m_statistics.skippedPrimitives = root.skipped;
    const SimdBox &rootBounds = root.bounds, &rootCentroids = root.centroids;
    m_statistics.primitives = refs.size();
    if (refs.empty())
        return;
    m_bounds = rootBounds.box();
    Builder builder(refs, intersectionCost, leafAlignment, m_bounds.getSurfaceArea());
    builder.build(0, static_cast<uint32_t>(refs.size()), rootBounds, rootCentroids, 0);

    // Collapse the binary tree into wide nodes in the SAH-optimal way.
    const CollapseCosts<Width> costs(builder);
    WideTreeWriter<Width> writer(builder, costs, refs, leafAlignment);
    const auto tree = writer.measure(0);
    // A leaf reference holds its first slot in 27 bits: 134M slots, padding included.
    if (tree.slots > static_cast<size_t>(BVHReference::kSlotMask) + 1)
        throw NoriException("{} primitives are more than one BVH holds: their leaves need "
                            "more than {} slots",
                            refs.size(), static_cast<size_t>(BVHReference::kSlotMask) + 1);
    m_nodes.resize(tree.nodes);
    m_primitiveOrder.resize(tree.slots);
    writer.write(0, 0, 0, m_nodes.data(), m_primitiveOrder.data());
    m_statistics.leaves = tree.leaves;
    m_statistics.maxDepth = tree.depth;
    m_statistics.sahCost = static_cast<float>(tree.sahCost);
    m_statistics.nodes = m_nodes.size();
}

template class BVH<4>;
template class BVH<8>;

} // namespace nori
