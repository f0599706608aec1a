#include <nori/accel.h>
#include <nori/mesh.h>
#include <nori/parallel.h>
#include <nori/triangle.h>

#include <iostream>

namespace nori {

namespace {

/// The box around a box's eight corners mapped by toWorld.
BoundingBox3f transformedBounds(const BoundingBox3f &box, const AffineMap &toWorld) {
    BoundingBox3f result;
    for (int corner = 0; corner < 8; ++corner) {
        const Point3f p((corner & 1) ? box.max.x() : box.min.x(),
                        (corner & 2) ? box.max.y() : box.min.y(),
                        (corner & 4) ? box.max.z() : box.min.z());
        result.expandBy(toWorld.applyToPoint(p));
    }
    return result;
}

} // namespace

void Accel::addShape(const Shape *shape) {
    m_shapes.push_back(shape);
    m_isMesh.push_back(dynamic_cast<const Mesh *>(shape) != nullptr);
    m_isMasked.push_back(shape->getOpacity() != nullptr);
    m_hasOpacity = m_hasOpacity || m_isMasked.back();
}

void Accel::addInstance(const InstanceTarget *target, const AffineMap &toWorld) {
    const int depth = target->accel->instanceDepth() + 1;
    if (depth > kMaxInstanceDepth)
        throw NoriException("instances nest {} levels deep; at most {} are supported", depth,
                            kMaxInstanceDepth);
    m_instanceDepth = std::max(m_instanceDepth, depth);
    auto [it, inserted] = m_targetIndex.emplace(target, static_cast<uint32_t>(m_targets.size()));
    if (inserted)
        m_targets.push_back(target);
    m_instances.push_back(
        {toWorld.inverse(), it->second, static_cast<uint32_t>(m_instances.size())});
    m_instanceBounds.push_back(transformedBounds(target->accel->getBoundingBox(), toWorld));
}

void Accel::build() {
    // Every primitive of every shape, numbered shape after shape: shape s holds primitives
    // [firstPrimitive[s], firstPrimitive[s + 1]).
    std::vector<size_t> firstPrimitive{0};
    for (const Shape *shape : m_shapes)
        firstPrimitive.push_back(firstPrimitive.back() + shape->getPrimitiveCount());
    auto locate = [&](size_t primitive) {
        const auto next =
            std::upper_bound(firstPrimitive.begin() + 1, firstPrimitive.end(), primitive);
        const auto shapeIndex = static_cast<uint32_t>(next - firstPrimitive.begin() - 1);
        return PrimitiveId{shapeIndex,
                           static_cast<uint32_t>(primitive - firstPrimitive[shapeIndex])};
    };
    m_bvh.build(
        firstPrimitive.back(),
        [&](size_t primitive) {
            const PrimitiveId id = locate(primitive);
            return m_shapes[id.shapeIndex]->getPrimitiveBoundingBox(id.primIndex);
        },
        BVHBase::kIntersectionCost, TrianglePacket::kWidth);
    m_bbox = m_bvh.getBoundingBox();

    // Copy the primitives into leaf order: triangles into packets of four slots.
    const std::vector<uint32_t> order = m_bvh.takePrimitiveOrder();
    const size_t packetCount = (order.size() + TrianglePacket::kWidth - 1) / TrianglePacket::kWidth;
    m_packets.resize(packetCount);
    parallelForChunks(size_t(0), packetCount, 1024, [&](size_t first, size_t last) {
        for (size_t packet = first; packet != last; ++packet)
            for (int lane = 0; lane < TrianglePacket::kWidth; ++lane) {
                const size_t slot = packet * TrianglePacket::kWidth + lane;
                m_packets[packet].clear(lane);
                if (slot >= order.size() || order[slot] == BVHBase::kNoPrimitive)
                    continue;
                const auto [shapeIndex, primIndex] = locate(order[slot]);
                m_packets[packet].shapeIndex[lane] = shapeIndex;
                m_packets[packet].primIndex[lane] = primIndex;
                if (!m_isMesh[shapeIndex])
                    continue;
                const auto *mesh = static_cast<const Mesh *>(m_shapes[shapeIndex]);
                const Vector3i &face = mesh->faces()[primIndex];
                const auto &positions = mesh->positions();
                m_packets[packet].setTriangle(lane, positions[face[0]], positions[face[1]],
                                              positions[face[2]]);
            }
    });

    // The instances, likewise in leaf order of their own tree.
    m_instanceBvh.build(m_instanceBounds, kInstanceIntersectionCost);
    std::vector<BoundingBox3f>().swap(m_instanceBounds);
    decltype(m_targetIndex)().swap(m_targetIndex);
    const std::vector<uint32_t> instanceOrder = m_instanceBvh.takePrimitiveOrder();
    std::vector<InstanceRecord> ordered(instanceOrder.size());
    for (size_t slot = 0; slot < instanceOrder.size(); ++slot)
        ordered[slot] = m_instances[instanceOrder[slot]];
    m_instances = std::move(ordered);
    m_bbox.expandBy(m_instanceBvh.getBoundingBox());

    const size_t left = m_bvh.statistics().skippedPrimitives;
    const size_t leftInstances = m_instanceBvh.statistics().skippedPrimitives;
    if (left > 0)
        std::cerr << "Warning: " << left
                  << " primitives with non-finite coordinates were left out of the scene\n";
    if (leftInstances > 0)
        std::cerr << "Warning: " << leftInstances
                  << " instances with empty or non-finite bounds were left out of the scene\n";
}

size_t Accel::memoryBytes() const {
    // NOLINTBEGIN(bugprone-sizeof-expression): two of the vectors hold pointers, whose
    // size is what they cost.
    return m_bvh.nodeCount() * sizeof(decltype(m_bvh)::Node) +
           m_packets.capacity() * sizeof(TrianglePacket) +
           m_instanceBvh.nodeCount() * sizeof(decltype(m_instanceBvh)::Node) +
           m_instances.capacity() * sizeof(InstanceRecord) +
           m_targets.capacity() * sizeof(decltype(m_targets)::value_type) +
           m_shapes.capacity() * sizeof(decltype(m_shapes)::value_type) + m_isMesh.capacity() +
           m_isMasked.capacity();
    // NOLINTEND(bugprone-sizeof-expression)
}

Ray3f Accel::toInstanceSpace(const AffineMap &toLocal, const Ray3f &ray, float tMax) {
    const Point3f o = toLocal.applyToPoint(ray.o);
    const Vector3f d = toLocal.applyToVector(ray.d);
    // The local origin lies within ±error of the exact image of ray.o: hits closer than
    // that along d may be the surface the ray was spawned from.
    const float lengthSquared = d.squaredNorm();
    const float dt = lengthSquared > 0.0f
                         ? d.cwiseAbs().dot(toLocal.roundingError(ray.o)) / lengthSquared
                         : 0.0f;
    return Ray3f(o, d, std::max(ray.mint, dt), tMax);
}

template <bool AnyHit> bool Accel::intersect(const Ray3f &ray, Hit &hit, int depth) const {
    bool found = false;
    float tBest = ray.maxt;

    if (!m_packets.empty()) {
        const WatertightRay watertightRay(ray);
        const WatertightRayPacket<4> packetRay(watertightRay);
#ifdef __AVX__
        const WatertightRayPacket<8> pairRay(watertightRay);
#endif
        uint32_t bestSlot = 0;
        Point2f bestCoords;
        // Each primitive is tested against the ray's full segment, and the closest hit is
        // kept (ties to the lower id); the BVH uses its distance to cull nodes. The packet
        // test decides the triangles; the few it leaves undecided, and other shapes, are
        // tested one by one. Inlined by force: GCC stopped inlining it into the grown
        // traversal, and the Cornell box rendered 3-7% slower.
        auto intersectLeaf = [&](uint32_t first, uint32_t count, float &tLimit)
            __attribute__((always_inline)) {
            bool hitInLeaf = false;
            auto consider = [&](uint32_t slot, float t, const Point2f &coords) {
                if (found && (t > tBest || (t == tBest && idOf(bestSlot) < idOf(slot))))
                    return false;
                // An alpha-masked surface is absent at some points: the ray goes on. Only
                // the masked shapes' hits are asked (from their position and uv alone).
                if (m_hasOpacity) {
                    const PrimitiveId id = idOf(slot);
                    if (m_isMasked[id.shapeIndex] &&
                        !m_shapes[id.shapeIndex]->presentAt(id.primIndex, ray, t, coords))
                        return false;
                }
                found = hitInLeaf = true;
                bestSlot = slot;
                tBest = tLimit = t;
                bestCoords = coords;
                return true;
            };
            // The lanes of `packets` from slot `base` on: the packet test's hits, then one by
            // one the lanes it left undecided and those of other shapes. True: stop (any hit).
            auto resolve = [&](const auto &hits, const TrianglePacket *packets, uint32_t base,
                               int lanes) {
                const int inLeaf = (1 << lanes) - 1;
                int triangles = 0;
                for (int p = 0; p * TrianglePacket::kWidth < lanes; ++p)
                    triangles |= packets[p].triangleLanes() << (p * TrianglePacket::kWidth);
                triangles &= inLeaf;
                for (int pending = hits.hit & triangles; pending != 0; pending &= pending - 1) {
                    const int lane = __builtin_ctz(static_cast<unsigned>(pending));
                    if (consider(base + lane, hits.t[lane],
                                 Point2f(hits.b1[lane], hits.b2[lane])) &&
                        AnyHit)
                        return true;
                }
                for (int pending = (hits.undecided & triangles) | (inLeaf & ~triangles);
                     pending != 0; pending &= pending - 1) {
                    const int lane = __builtin_ctz(static_cast<unsigned>(pending));
                    const uint32_t slot = base + lane;
                    const TrianglePacket &packet = packets[lane / TrianglePacket::kWidth];
                    const int packetLane = lane % TrianglePacket::kWidth;
                    float t;
                    Point2f coords;
                    const bool hit =
                        (triangles >> lane) & 1
                            ? intersectTriangle(watertightRay, packet.vertex(packetLane, 0),
                                                packet.vertex(packetLane, 1),
                                                packet.vertex(packetLane, 2), t, coords.x(),
                                                coords.y())
                            : m_shapes[packet.shapeIndex[packetLane]]->rayIntersect(
                                  packet.primIndex[packetLane], ray, t, coords);
                    if (hit && consider(slot, t, coords) && AnyHit)
                        return true;
                }
                return false;
            };
            for (uint32_t base = first; base < first + count;) {
                const TrianglePacket *packets = &m_packets[base / TrianglePacket::kWidth];
                const uint32_t remaining = first + count - base;
#ifdef __AVX__
                // Two packets at once: one eight-lane test costs what a four-lane one does.
                if (remaining > TrianglePacket::kWidth) {
                    const int lanes =
                        static_cast<int>(std::min(2u * TrianglePacket::kWidth, remaining));
                    if (resolve(pairRay.intersect(packets[0], packets[1]), packets, base, lanes))
                        return true;
                    base += 2 * TrianglePacket::kWidth;
                    continue;
                }
#endif
                const int lanes =
                    static_cast<int>(std::min<uint32_t>(TrianglePacket::kWidth, remaining));
                if (resolve(packetRay.intersect(packets[0]), packets, base, lanes))
                    return true;
                base += TrianglePacket::kWidth;
            }
            return hitInLeaf;
        };
        // A leaf's packets are contiguous: prefetch every cache line they touch.
        auto prefetchLeaf = [&](uint32_t first, uint32_t count) {
            const auto *begin =
                reinterpret_cast<const char *>(&m_packets[first / TrianglePacket::kWidth]);
            const auto *end = reinterpret_cast<const char *>(
                &m_packets[(first + count - 1) / TrianglePacket::kWidth] + 1);
            // From the start of the first packet's cache line.
            for (const char *line = begin - reinterpret_cast<uintptr_t>(begin) % 64; line < end;
                 line += 64)
                __builtin_prefetch(line);
        };
        float tLimit = ray.maxt;
        m_bvh.traverse<AnyHit>(ray, tLimit, intersectLeaf, prefetchLeaf);
        if (found) {
            if (AnyHit)
                return true;
            hit.t = tBest;
            hit.coords = bestCoords;
            hit.owner = this;
            hit.slot = bestSlot;
            hit.depth = depth;
        }
    }

    if (!m_instances.empty()) {
        // A primitive of this Accel wins a tie in t against an instance; among
        // instances, the earlier one added wins.
        const InstanceRecord *bestInstance = nullptr;
        Hit inner;
        auto intersectInstance = [&](uint32_t slot, float &tLimit) {
            const InstanceRecord &instance = m_instances[slot];
            const Ray3f local = toInstanceSpace(instance.toLocal, ray, tBest);
            if (local.mint > local.maxt ||
                !m_targets[instance.target]->accel->intersect<AnyHit>(local, inner, depth + 1))
                return false;
            if (found && inner.t == tBest &&
                (bestInstance == nullptr || bestInstance->order < instance.order))
                return false;
            found = true;
            bestInstance = &instance;
            if (AnyHit)
                return true;
            hit = inner;
            hit.path[depth] = &instance;
            tBest = tLimit = inner.t;
            return true;
        };
        auto intersectLeaf = [&](uint32_t first, uint32_t count, float &tLimit) {
            bool hitInLeaf = false;
            for (uint32_t slot = first; slot < first + count; ++slot)
                if (intersectInstance(slot, tLimit)) {
                    hitInLeaf = true;
                    if (AnyHit)
                        return true;
                }
            return hitInLeaf;
        };
        float tLimit = tBest;
        m_instanceBvh.traverse<AnyHit>(ray, tLimit, intersectLeaf, [](uint32_t, uint32_t) {});
    }
    return found;
}

bool Accel::closestHit(const Ray3f &ray, float &t, const Shape *&shape, uint32_t &primIndex) const {
    Hit hit;
    if (!intersect<false>(ray, hit, 0))
        return false;
    t = hit.t;
    const PrimitiveId id = hit.owner->idOf(hit.slot);
    const Shape *reportedShape = followInstances(hit, nullptr);
    shape = reportedShape ? reportedShape : hit.owner->m_shapes[id.shapeIndex];
    primIndex = id.primIndex;
    return true;
}

const Shape *Accel::followInstances(const Hit &hit, AffineMap *toLocal) const {
    const Shape *reportedShape = nullptr;
    const Accel *accel = this;
    for (int level = 0; level < hit.depth; ++level) {
        const InstanceRecord &instance = *hit.path[level];
        if (toLocal)
            *toLocal = instance.toLocal * *toLocal;
        const InstanceTarget *target = accel->m_targets[instance.target];
        reportedShape = target->reportedShape;
        accel = target->accel;
    }
    return reportedShape;
}

bool Accel::rayIntersect(const Ray3f &ray, Intersection &its, bool shadowRay) const {
    Hit hit;
    if (shadowRay ? !intersect<true>(ray, hit, 0) : !intersect<false>(ray, hit, 0))
        return false;
    if (shadowRay)
        return true;

    AffineMap toLocal;
    const Shape *reportedShape = followInstances(hit, &toLocal);

    its.t = hit.t;
    const PrimitiveId id = hit.owner->idOf(hit.slot);
    const Shape *shape = hit.owner->m_shapes[id.shapeIndex];
    if (hit.depth == 0) {
        shape->setHitInformation(id.primIndex, ray, hit.coords, its);
        return true;
    }
    Ray3f localRay(toLocal.applyToPoint(ray.o), toLocal.applyToVector(ray.d), ray.mint, ray.maxt);
    shape->setInstancedHitInformation(id.primIndex, localRay, hit.coords, toLocal.inverse(),
                                      toLocal, its);
    if (reportedShape)
        its.shape = its.mesh = reportedShape;
    return true;
}

} // namespace nori
