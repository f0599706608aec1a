#include <nori/bsdf.h>
#include <nori/emitter.h>
#include <nori/rayerror.h>
#include <nori/shape.h>

namespace nori {

Ray3f Intersection::spawnRay(const Vector3f &d) const {
    return Ray3f(offsetRayOrigin(p, pError, geoFrame.n, d), d, 0.0f, kInfinity);
}

Ray3f Intersection::spawnRayTo(const Point3f &target) const {
    const Point3f origin = offsetRayOrigin(p, pError, geoFrame.n, target - p);
    const Vector3f d = target - origin;
    const float distance = d.norm();
    // Stop a relative 1e-4 short of the target (PBR's ShadowEpsilon), so the surface the
    // target lies on does not count as an occluder.
    return Ray3f(origin, d / distance, 0.0f, distance * (1.0f - kShadowEpsilon));
}

void Shape::addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) {
    if (child->getClassType() == EBSDF) {
        setUniqueChild(m_bsdf, child, "a shape");
    } else if (child->getClassType() == EEmitter) {
        setUniqueChild(m_emitter, child, "a shape");
        m_emitter->setShape(this);
    } else {
        NoriObject::addChild(child, name);
    }
}

ShapeSample Shape::sampleFromReference(const Point3f &ref, const Point2f &sample) const {
    ShapeSample result = sampleSurface(sample);
    result.pdf = pdfFromReference(ref, result.p, result.n);
    return result;
}

float Shape::pdfFromReference(const Point3f &ref, const Point3f &p, const Normal3f &n) const {
    // Change of measure from area to solid angle at ref: dω = |cos θ| dA / d².
    const Vector3f toPoint = p - ref;
    const float distanceSquared = toPoint.squaredNorm();
    const float cosTheta = std::abs(n.dot(toPoint)) / std::sqrt(distanceSquared);
    if (cosTheta == 0.0f || distanceSquared == 0.0f)
        return 0.0f;
    return distanceSquared / (cosTheta * getArea());
}

void Shape::activate() {
    if (m_emitter && !(getArea() > 0.0f))
        throw NoriException("an area light needs a surface to emit from, but {} has none (no "
                            "usable triangles)",
                            toString());
    if (!m_bsdf)
        m_bsdf = createDefault<BSDF>("diffuse");
}

} // namespace nori
