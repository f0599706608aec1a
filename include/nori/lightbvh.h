// Choosing a light for next-event estimation by its importance at the shading point: a
// bounding volume hierarchy over the lights' bounds (Estevez and Kulla 2018; PBR 4th ed.
// §12.6.3). Each step down the tree picks a child in proportion to the importance of its
// bounds at the point, so near, bright lights facing the point are chosen most, and the
// probability of any light is the product of the choices on its path from the root.
#pragma once

#include <nori/lightbounds.h>

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace nori {

class Emitter;

class LightBVH {
public:
    /// Builds the tree over the lights that have bounds (Emitter::lightBounds) and some
    /// power; the others (lights at infinity, directional lights, plugins that give no
    /// bounds) are chosen beside it, each as likely as the whole tree.
    void build(const std::vector<std::shared_ptr<Emitter>> &emitters);

    /// Picks a light for the point p (n: its surface normal, or zero in a medium) and
    /// sets pmf to its probability; `u` is rescaled for reuse. nullptr when no light can
    /// reach p.
    const Emitter *sample(const Point3f &p, const Normal3f &n, float &u, float &pmf) const;
    /// The probability that sample() picks `emitter` at p.
    float pmf(const Point3f &p, const Normal3f &n, const Emitter *emitter) const;

    /// The number of nodes of the tree and of lights beside it (for statistics).
    size_t nodeCount() const { return m_nodes.size(); }
    size_t unboundedCount() const { return m_unbounded.size(); }

private:
    /// A node: its bounds, and either the index of its second child (the first follows
    /// it) or of its light in m_lights.
    struct Node {
        LightImportance importance;
        uint32_t childOrLight = 0;
        bool isLeaf = false;
    };
    /// The path from the root to a leaf: bit d is the child taken at depth d.
    struct Trail {
        uint64_t bits = 0;
        uint32_t depth = 0;
    };

    /// Builds the subtree over lights[begin, end) and returns its root's index and bounds.
    std::pair<uint32_t, LightBounds>
    buildRecursive(std::vector<std::pair<uint32_t, LightBounds>> &lights, size_t begin, size_t end,
                   Trail trail);
    /// The probability of the tree as a whole against the lights beside it.
    float treeProbability() const;

    std::vector<Node> m_nodes;
    std::vector<const Emitter *> m_lights;    ///< the lights with bounds, by leaf
    std::vector<const Emitter *> m_unbounded; ///< chosen uniformly beside the tree
    std::unordered_map<const Emitter *, Trail> m_trails;
    std::unordered_set<const Emitter *> m_isUnbounded;
};

} // namespace nori
