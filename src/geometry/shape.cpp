#include <nori/hash.h>
#include <nori/instance.h>
#include <nori/proplist.h>
#include <nori/rayerror.h>
#include <nori/shape.h>

#include <iostream>

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

void Shape::setInstancedHitInformation(uint32_t index, const Ray3f &ray, const Point2f &hitCoords,
                                       const AffineMap &toWorld, const AffineMap &toLocal,
                                       Intersection &its) const {
    setHitInformation(index, ray, hitCoords, its);
    const Point3f localP = its.p;
    its.p = toWorld.applyToPoint(localP);
    // toWorld is the rounded inverse of toLocal: one rounding (γ₁ ≈ γ₃/3) more than
    // pbrt's bound for an exact matrix.
    its.pError = toWorld.propagatedError(localP, its.pError) + toWorld.roundingError(localP) / 3.0f;

    its.geoFrame = Frame(toLocal.applyTransposeToNormal(its.geoFrame.n).normalized());
    const Vector3f worldNormal = toLocal.applyTransposeToNormal(its.shFrame.n);
    const Vector3f shadingNormal = worldNormal.normalized();
    Vector3f tangent = toWorld.applyToVector(its.shFrame.s);
    tangent -= shadingNormal * shadingNormal.dot(tangent);
    its.shFrame =
        tangent.squaredNorm() > 1e-20f
            ? Frame(tangent.normalized(), shadingNormal.cross(tangent.normalized()), shadingNormal)
            : Frame(shadingNormal);
    its.dpdu = toWorld.applyToVector(its.dpdu);
    its.dpdv = toWorld.applyToVector(its.dpdv);
    // The normal field maps by Aᵀ and is then normalised: its derivatives scale by the
    // same 1/|Aᵀn| to first order, so they stay those of a unit-length field.
    const float normalScale = 1.0f / worldNormal.norm();
    its.dndu = normalScale * toLocal.applyTransposeToNormal(its.dndu);
    its.dndv = normalScale * toLocal.applyTransposeToNormal(its.dndv);
}

bool surfacePresent(float alpha, const Point3f &p) {
    if (alpha >= 1.0f)
        return true;
    if (!(alpha > 0.0f))
        return false;
    return hashToUnitFloat(hashFloats(p.x(), p.y(), p.z())) < alpha;
}

void Shape::setOpacity(std::shared_ptr<const SurfaceOpacity> opacity) {
    if (m_opacity)
        throw NoriException("a shape takes only one alpha mask");
    m_opacity = std::move(opacity);
}

void Shape::hitPoint(uint32_t index, const Ray3f &ray, float t, const Point2f &hitCoords,
                     Point3f &p, Point2f &uv) const {
    Intersection its;
    its.t = t;
    setHitInformation(index, ray, hitCoords, its);
    p = its.p;
    uv = its.uv;
}

bool Shape::presentAt(uint32_t index, const Ray3f &ray, float t, const Point2f &hitCoords) const {
    if (!m_opacity)
        return true;
    Point3f p;
    Point2f uv;
    hitPoint(index, ray, t, hitCoords, p, uv);
    return surfacePresent(m_opacity->opacityAtHit(uv, p), p);
}

void Shape::setBSDF(std::shared_ptr<BSDF> bsdf) {
    if (m_bsdf)
        throw NoriException("a shape takes only one bsdf");
    m_bsdf = std::move(bsdf);
}

void Shape::setEmitter(std::shared_ptr<Emitter> emitter) {
    if (m_emitter)
        throw NoriException("a shape takes only one emitter");
    m_emitter = std::move(emitter);
}

void Shape::setMedium(const std::string &side, std::shared_ptr<Medium> medium) {
    if (side != "interior" && side != "exterior")
        throw NoriException("a shape's medium is named \"interior\" or \"exterior\", not "
                            "\"{}\"",
                            side);
    std::shared_ptr<Medium> &slot = side == "interior" ? m_interior : m_exterior;
    if (slot)
        throw NoriException("a shape's {} takes only one medium", side);
    slot = std::move(medium);
}

void Shape::setSurfaceShading(std::shared_ptr<const SurfaceShading> shading) {
    m_shading = std::move(shading);
}

void Shape::addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) {
    if (const auto *tmesh = dynamic_cast<const TMesh *>(child.get())) {
        if (!m_tmeshes)
            m_tmeshes = std::make_shared<TMeshSet>(*this);
        m_tmeshes->add(*tmesh);
    } else if (child->attachTo(*this, name)) {
        // a BSDF, an area light or a medium: it filled its slot
    } else if (child->getClassType() == EMesh) {
        throw NoriException("a shape holds no other shapes, only <mesh type=\"tmesh\"> copies of "
                            "itself; put <{} type=\"{}\"> beside it",
                            classTypeName(child->getClassType()), child->pluginName());
    } else {
        NoriObject::addChild(child, name);
    }
}

ShapeSample Shape::sampleFromReference(const Point3f &ref, const Normal3f &,
                                       const Point2f &sample) const {
    return areaSampleFromReference(ref, sample);
}

ShapeSample Shape::areaSampleFromReference(const Point3f &ref, const Point2f &sample) const {
    ShapeSample result = sampleSurface(sample);
    result.pdf = areaPdfFromReference(ref, result.p, result.n);
    return result;
}

float Shape::pdfFromReference(const Point3f &ref, const Normal3f &,
                              const ShapeSample &point) const {
    return areaPdfFromReference(ref, point.p, point.n);
}

float Shape::areaPdfFromReference(const Point3f &ref, const Point3f &p, const Normal3f &n) const {
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
    if (!m_bsdf) {
        // Nori's default: a diffuse surface; a medium boundary's default lets light through.
        auto bsdf = NoriObjectFactory::createInstance(hasMediumInterface() ? "null" : "diffuse",
                                                      EBSDF, PropertyList());
        bsdf->attachTo(*this, "");
    }
    if (m_interior && !isClosed())
        std::cerr << fmt::format("Warning: {} has an interior medium but is not closed (some "
                                 "edges border one triangle): rays can reach the medium without "
                                 "entering it\n",
                                 toString());
    if (m_tmeshes) {
        if (m_emitter)
            throw NoriException("an area light on a shape with tmesh copies is not supported: "
                                "instanced geometry does not emit (give each light its own mesh)");
        if (hasMediumInterface())
            throw NoriException("a medium on a shape with tmesh copies is not supported: give "
                                "each medium boundary its own mesh");
        m_tmeshes->build();
    }
    if (m_opacity && hasMediumInterface())
        throw NoriException("{} has an alpha mask and bounds a medium: a boundary with holes "
                            "leaves the medium undefined",
                            toString());
    if (!m_visible && m_emitter)
        throw NoriException("an invisible shape (visible = false) cannot carry an area light");
}

} // namespace nori
