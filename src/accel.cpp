#include <nori/accel.h>

namespace nori {

void Accel::addShape(const Shape *shape) {
    m_shapes.push_back(shape);
    m_bbox.expandBy(shape->getBoundingBox());
}

void Accel::build() {}

bool Accel::rayIntersect(const Ray3f &rayIn, Intersection &its, bool shadowRay) const {
    Ray3f ray(rayIn);
    const Shape *hitShape = nullptr;
    uint32_t hitIndex = 0;
    Point2f hitCoords;

    for (const Shape *shape : m_shapes) {
        const uint32_t count = shape->getPrimitiveCount();
        for (uint32_t index = 0; index < count; ++index) {
            float t;
            Point2f coords;
            if (!shape->rayIntersect(index, ray, t, coords))
                continue;
            if (shadowRay)
                return true;
            ray.maxt = t; // later hits must be closer
            hitShape = shape;
            hitIndex = index;
            hitCoords = coords;
        }
    }
    if (!hitShape)
        return false;
    its.t = ray.maxt;
    hitShape->setHitInformation(hitIndex, ray, hitCoords, its);
    return true;
}

} // namespace nori
