#include <nori/bsdf.h>
#include <nori/shape.h>

namespace nori {

namespace {

/// Pushes p off the surface along the geometric normal, to the side `d` points to.
/// The offset scales with the magnitude of p, since float round-off does.
Point3f offsetOrigin(const Point3f &p, const Normal3f &n, const Vector3f &d) {
    float offset = kEpsilon * std::max(1.0f, p.cwiseAbs().maxCoeff());
    return p + (n.dot(d) >= 0.0f ? offset : -offset) * n;
}

} // namespace

Ray3f Intersection::spawnRay(const Vector3f &d) const {
    return Ray3f(offsetOrigin(p, geoFrame.n, d), d, 0.0f, kInfinity);
}

Ray3f Intersection::spawnRayTo(const Point3f &target) const {
    Point3f origin = offsetOrigin(p, geoFrame.n, target - p);
    Vector3f d = target - origin;
    float distance = d.norm();
    // Stop short of the target by the same relative margin, so a light's own surface
    // does not count as an occluder.
    float margin = kEpsilon * std::max(1.0f, target.cwiseAbs().maxCoeff());
    return Ray3f(origin, d / distance, 0.0f, std::max(0.0f, distance - margin));
}

void Shape::addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) {
    if (child->getClassType() == EBSDF)
        setUniqueChild(m_bsdf, child, "a shape");
    else
        NoriObject::addChild(child, name);
}

void Shape::activate() {
    if (!m_bsdf)
        m_bsdf = createDefault<BSDF>("diffuse");
}

} // namespace nori
