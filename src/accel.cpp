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
    m_primitives.resize(order.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, order.size(), 4096),
                      [&](const tbb::blocked_range<size_t> &range) {
                          for (size_t slot = range.begin(); slot != range.end(); ++slot) {
                              const auto [shapeIndex, primIndex] = refs[order[slot]];
                              Primitive &primitive = m_primitives[slot];
                              primitive.shapeIndex = shapeIndex;
                              primitive.primIndex = primIndex;
                              if (!m_isMesh[shapeIndex])
                                  continue;
                              const auto *mesh = static_cast<const Mesh *>(m_shapes[shapeIndex]);
                              const Vector3i &face = mesh->getFaces()[primIndex];
                              primitive.p0 = mesh->getVertexPositions()[face[0]];
                              primitive.p1 = mesh->getVertexPositions()[face[1]];
                              primitive.p2 = mesh->getVertexPositions()[face[2]];
                          }
                      });
}

bool Accel::rayIntersect(const Ray3f &ray, Intersection &its, bool shadowRay) const {
    const WatertightRay watertightRay(ray);
    float tBest = ray.maxt;
    const Primitive *best = nullptr;
    Point2f bestCoords;

    // Each primitive is tested against the ray's full segment; the closest hit (ties to
    // the lower index) is kept and only used to cull nodes.
    auto intersect = [&](uint32_t slot, float &tMax) {
        const Primitive &primitive = m_primitives[slot];
        float t;
        Point2f coords;
        if (m_isMesh[primitive.shapeIndex]) {
            if (!intersectTriangle(watertightRay, primitive.p0, primitive.p1, primitive.p2, t,
                                   coords.x(), coords.y()))
                return false;
        } else if (!m_shapes[primitive.shapeIndex]->rayIntersect(primitive.primIndex, ray, t,
                                                                 coords)) {
            return false;
        }
        if (best &&
            (t > tBest || (t == tBest && std::make_pair(primitive.shapeIndex, primitive.primIndex) >
                                             std::make_pair(best->shapeIndex, best->primIndex))))
            return false;
        best = &primitive;
        tBest = tMax = t;
        bestCoords = coords;
        return true;
    };
    float tMax = ray.maxt;
    if (!m_bvh.traverse(ray, tMax, shadowRay, intersect) || !best)
        return false;
    if (shadowRay)
        return true;
    its.t = tBest;
    m_shapes[best->shapeIndex]->setHitInformation(best->primIndex, ray, bestCoords, its);
    return true;
}

} // namespace nori
