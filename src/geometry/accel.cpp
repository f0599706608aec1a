#include <nori/accel.h>
#include <nori/mesh.h>
#include <nori/triangle.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <iostream>

namespace nori {

void Accel::addShape(const Shape *shape) {
    m_shapes.push_back(shape);
    m_isMesh.push_back(dynamic_cast<const Mesh *>(shape) != nullptr);
}

void Accel::build() {
    // Every primitive of every shape, with its bounds.
    std::vector<std::pair<uint32_t, uint32_t>> refs; // (shape, primitive)
    for (uint32_t s = 0; s < m_shapes.size(); ++s)
        for (uint32_t p = 0; p < m_shapes[s]->getPrimitiveCount(); ++p)
            refs.emplace_back(s, p);
    std::vector<BoundingBox3f> bounds(refs.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, refs.size(), 4096),
                      [&](const tbb::blocked_range<size_t> &range) {
                          for (size_t i = range.begin(); i != range.end(); ++i)
                              bounds[i] =
                                  m_shapes[refs[i].first]->getPrimitiveBoundingBox(refs[i].second);
                      });
    m_bvh.build(bounds);
    m_bbox = m_bvh.getBoundingBox();
    if (m_bvh.statistics().skippedPrimitives > 0)
        std::cerr << "Warning: " << m_bvh.statistics().skippedPrimitives
                  << " primitives with non-finite coordinates were left out of the scene\n";

    // Copy the primitives into leaf order.
    const std::vector<uint32_t> &order = m_bvh.primitiveOrder();
    m_triangles.resize(order.size());
    m_ids.resize(order.size());
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, order.size(), 4096),
        [&](const tbb::blocked_range<size_t> &range) {
            for (size_t slot = range.begin(); slot != range.end(); ++slot) {
                const auto [shapeIndex, primIndex] = refs[order[slot]];
                m_ids[slot] = {shapeIndex, primIndex};
                if (!m_isMesh[shapeIndex]) {
                    m_triangles[slot].p0.x() = std::numeric_limits<float>::quiet_NaN();
                    continue;
                }
                const auto *mesh = static_cast<const Mesh *>(m_shapes[shapeIndex]);
                const Vector3i &face = mesh->getFaces()[primIndex];
                const auto &positions = mesh->getVertexPositions();
                m_triangles[slot] = {positions[face[0]], positions[face[1]], positions[face[2]]};
            }
        });
}

bool Accel::rayIntersect(const Ray3f &ray, Intersection &its, bool shadowRay) const {
    const WatertightRay watertightRay(ray);
    float tBest = ray.maxt;
    uint32_t bestSlot = 0;
    bool found = false;
    Point2f bestCoords;

    // Each primitive is tested against the ray's full segment, and the closest hit is
    // kept (ties to the lower id); the BVH uses its distance to cull nodes.
    auto intersect = [&](uint32_t slot, float &tMax) {
        float t;
        Point2f coords;
        const TriangleVertices &v = m_triangles[slot];
        if (v.isTriangle()) {
            if (!intersectTriangle(watertightRay, v.p0, v.p1, v.p2, t, coords.x(), coords.y()))
                return false;
        } else if (!m_shapes[m_ids[slot].shapeIndex]->rayIntersect(m_ids[slot].primIndex, ray, t,
                                                                   coords)) {
            return false;
        }
        if (found && (t > tBest || (t == tBest && m_ids[bestSlot] < m_ids[slot])))
            return false;
        found = true;
        bestSlot = slot;
        tBest = tMax = t;
        bestCoords = coords;
        return true;
    };
    float tMax = ray.maxt;
    auto prefetch = [&](uint32_t slot) { __builtin_prefetch(&m_triangles[slot]); };
    if (!m_bvh.traverse(ray, tMax, shadowRay, intersect, prefetch))
        return false;
    if (shadowRay)
        return true;
    its.t = tBest;
    const PrimitiveId &id = m_ids[bestSlot];
    m_shapes[id.shapeIndex]->setHitInformation(id.primIndex, ray, bestCoords, its);
    return true;
}

} // namespace nori
