#include <nori/emitter.h>
#include <nori/lightbvh.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace nori {

namespace {

/// The largest float below 1, so that a rescaled sample stays in [0, 1).
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

/// Buckets per axis for the split search (PBR 4th ed. §12.6.3 uses 12).
constexpr int kBuckets = 12;
/// From this depth on, nodes are split at the median count, so that every path from
/// the root fits the 64 bits of a Trail.
constexpr uint32_t kMaxCostDepth = 40;

/// The cost of a cluster on one side of a split along `axis` of the parent box
/// (PBR 4th ed. §12.6.3, EvaluateCost): power × orientation measure × surface area,
/// with splits across thin axes penalised by the ratio of the box's longest side to the
/// split axis' side.
float splitCost(const LightBounds &cluster, const BoundingBox3f &parent, int axis) {
    const Vector3f extents = parent.getExtents();
    const float regulariser = extents.maxCoeff() / extents[axis];
    return cluster.phi * cluster.orientationMeasure() * regulariser *
           cluster.bounds.getSurfaceArea();
}

} // namespace

void LightBVH::build(const std::vector<std::shared_ptr<Emitter>> &emitters) {
    m_nodes.clear();
    m_lights.clear();
    m_unbounded.clear();
    m_trails.clear();
    m_isUnbounded.clear();
    std::vector<std::pair<uint32_t, LightBounds>> bounded;
    for (const auto &emitter : emitters) {
        // A dark light sends nothing: it is never chosen (its probability is 0).
        if (!(emitter->getPower().getLuminance() > 0.0f))
            continue;
        if (const std::optional<LightBounds> bounds = emitter->lightBounds();
            bounds && bounds->phi > 0.0f) {
            bounded.emplace_back(static_cast<uint32_t>(m_lights.size()), *bounds);
            m_lights.push_back(emitter.get());
        } else {
            m_unbounded.push_back(emitter.get());
            m_isUnbounded.insert(emitter.get());
        }
    }
    if (!bounded.empty())
        buildRecursive(bounded, 0, bounded.size(), Trail{});
}

std::pair<uint32_t, LightBounds>
LightBVH::buildRecursive(std::vector<std::pair<uint32_t, LightBounds>> &lights, size_t begin,
                         size_t end, Trail trail) {
    const auto nodeIndex = static_cast<uint32_t>(m_nodes.size());
    m_nodes.emplace_back();
    if (end - begin == 1) {
        m_nodes[nodeIndex] = Node{LightImportance(lights[begin].second), lights[begin].first, true};
        m_trails[m_lights[lights[begin].first]] = trail;
        return {nodeIndex, lights[begin].second};
    }

    BoundingBox3f box, centroids;
    for (size_t i = begin; i < end; ++i) {
        box.expandBy(lights[i].second.bounds);
        centroids.expandBy(lights[i].second.bounds.getCenter());
    }
    // The split of least cost among kBuckets − 1 planes along each axis.
    float bestCost = kInfinity;
    int bestAxis = -1, bestBucket = -1;
    const auto bucketOf = [&](const LightBounds &bounds, int axis) {
        const float offset = (bounds.bounds.getCenter()[axis] - centroids.min[axis]) /
                             (centroids.max[axis] - centroids.min[axis]);
        return std::clamp(static_cast<int>(offset * kBuckets), 0, kBuckets - 1);
    };
    for (int axis = 0; axis < 3 && trail.depth < kMaxCostDepth; ++axis) {
        if (!(centroids.max[axis] > centroids.min[axis]))
            continue;
        std::array<LightBounds, kBuckets> buckets{};
        for (size_t i = begin; i < end; ++i) {
            LightBounds &bucket = buckets[bucketOf(lights[i].second, axis)];
            bucket = lightBoundsUnion(bucket, lights[i].second);
        }
        for (int split = 0; split < kBuckets - 1; ++split) {
            LightBounds below, above;
            for (int b = 0; b <= split; ++b)
                below = lightBoundsUnion(below, buckets[b]);
            for (int b = split + 1; b < kBuckets; ++b)
                above = lightBoundsUnion(above, buckets[b]);
            if (below.phi == 0.0f || above.phi == 0.0f)
                continue;
            const float cost = splitCost(below, box, axis) + splitCost(above, box, axis);
            if (cost < bestCost) {
                bestCost = cost;
                bestAxis = axis;
                bestBucket = split;
            }
        }
    }
    const auto first = lights.begin() + static_cast<std::ptrdiff_t>(begin);
    const auto last = lights.begin() + static_cast<std::ptrdiff_t>(end);
    auto middle = first;
    if (bestAxis >= 0)
        middle = std::partition(first, last, [&](const auto &light) {
            return bucketOf(light.second, bestAxis) <= bestBucket;
        });
    if (middle == first || middle == last) {
        // No useful plane (coincident lights, or too deep): halve by count.
        middle = first + static_cast<std::ptrdiff_t>((end - begin) / 2);
        const int axis = centroids.getMajorAxis();
        std::nth_element(first, middle, last, [axis](const auto &a, const auto &b) {
            return a.second.bounds.getCenter()[axis] < b.second.bounds.getCenter()[axis];
        });
    }
    const auto mid = static_cast<size_t>(middle - lights.begin());
    // The first child follows its parent in m_nodes; the parent keeps the second's index.
    const LightBounds firstBounds =
        buildRecursive(lights, begin, mid, Trail{trail.bits, trail.depth + 1}).second;
    const auto [secondIndex, secondBounds] = buildRecursive(
        lights, mid, end, Trail{trail.bits | (uint64_t(1) << trail.depth), trail.depth + 1});
    const LightBounds bounds = lightBoundsUnion(firstBounds, secondBounds);
    m_nodes[nodeIndex] = Node{LightImportance(bounds), secondIndex, false};
    return {nodeIndex, bounds};
}

float LightBVH::treeProbability() const {
    return m_nodes.empty() ? 0.0f : 1.0f / static_cast<float>(m_unbounded.size() + 1);
}

const Emitter *LightBVH::sample(const Point3f &p, const Normal3f &n, float &u, float &pmf) const {
    const float pTree = treeProbability();
    const float pBeside = 1.0f - pTree;
    if (u < pBeside) {
        // One of the lights beside the tree, uniformly.
        const float scaled = u / pBeside * static_cast<float>(m_unbounded.size());
        const size_t index = std::min(static_cast<size_t>(scaled), m_unbounded.size() - 1);
        u = std::min(scaled - static_cast<float>(index), kOneMinusEpsilon);
        pmf = pBeside / static_cast<float>(m_unbounded.size());
        return m_unbounded[index];
    }
    // The walk works on copies of u and pmf (references might alias), kept in registers.
    float walkU = std::min((u - pBeside) / pTree, kOneMinusEpsilon);
    float walkPmf = pTree;
    uint32_t index = 0;
    while (!m_nodes[index].isLeaf) {
        const Node &node = m_nodes[index];
        const float first = m_nodes[index + 1].importance(p, n);
        const float second = m_nodes[node.childOrLight].importance(p, n);
        if (!(first + second > 0.0f))
            break;
        // The same two quotients as pmf() computes.
        const float pFirst = first / (first + second), pSecond = second / (first + second);
        if (walkU < pFirst) {
            walkU = std::min(walkU / pFirst, kOneMinusEpsilon);
            walkPmf *= pFirst;
            index = index + 1;
        } else {
            walkU = std::min((walkU - pFirst) / pSecond, kOneMinusEpsilon);
            walkPmf *= pSecond;
            index = node.childOrLight;
        }
    }
    u = walkU;
    const Node &node = m_nodes[index];
    // A leaf reached by choices has importance; a lone light at the root may have none.
    if (node.isLeaf && (index > 0 || node.importance(p, n) > 0.0f)) {
        pmf = walkPmf;
        return m_lights[node.childOrLight];
    }
    pmf = 0.0f;
    return nullptr;
}

float LightBVH::pmf(const Point3f &p, const Normal3f &n, const Emitter *emitter) const {
    if (m_isUnbounded.count(emitter) != 0)
        return (1.0f - treeProbability()) / static_cast<float>(m_unbounded.size());
    const auto found = m_trails.find(emitter);
    if (found == m_trails.end())
        return 0.0f;
    const Trail &trail = found->second;
    float pmf = treeProbability();
    uint32_t index = 0;
    for (uint32_t depth = 0; !m_nodes[index].isLeaf; ++depth) {
        const Node &node = m_nodes[index];
        const float first = m_nodes[index + 1].importance(p, n);
        const float second = m_nodes[node.childOrLight].importance(p, n);
        if (!(first + second > 0.0f))
            return 0.0f;
        const bool takesSecond = ((trail.bits >> depth) & 1) != 0;
        pmf *= (takesSecond ? second : first) / (first + second);
        index = takesSecond ? node.childOrLight : index + 1;
    }
    return index > 0 || m_nodes[index].importance(p, n) > 0.0f ? pmf : 0.0f;
}

} // namespace nori
