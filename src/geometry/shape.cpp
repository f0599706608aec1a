#include <nori/bsdf.h>
#include <nori/emitter.h>
#include <nori/instance.h>
#include <nori/proplist.h>
#include <nori/raydifferential.h>
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

void Shape::readSurfaceParameters(const PropertyList &props) {
    m_uvScale = props.holdsScalar("uvScale") ? Vector2f::Constant(props.getFloat("uvScale"))
                                             : props.getVector2("uvScale", Vector2f(1.0f, 1.0f));
    if (!(m_uvScale.allFinite() && m_uvScale.x() != 0.0f && m_uvScale.y() != 0.0f))
        throw NoriException("'uvScale' must be finite and non-zero");
    auto dataTexture = [&](const char *name) -> std::shared_ptr<const Texture> {
        if (!props.holdsObject(name)) {
            if (props.has(name))
                throw NoriException("'{}' must be a <texture name=\"{}\">", name, name);
            return nullptr;
        }
        auto texture = std::dynamic_pointer_cast<const Texture>(props.getObject(name));
        if (!texture)
            throw NoriException("'{}' must be a texture", name);
        // Normal and height maps hold data: 8-bit images are not sRGB-decoded.
        auto linear = texture->linearVariant();
        return linear ? linear : texture;
    };
    m_normalMap = dataTexture("normal");
    m_bumpMap = dataTexture("bump");
    m_bumpScale = props.getFloat("bumpScale", 1.0f);
    m_visible = props.getBoolean("visible", true);
    if (m_normalMap && m_bumpMap)
        throw NoriException("give a 'normal' map or a 'bump' map, not both");
    if (!std::isfinite(m_bumpScale))
        throw NoriException("'bumpScale' must be finite");
}

namespace {

/// Smallest cosine between the viewer and a perturbed shading normal (see completeHit).
constexpr float kMinShadingCosine = 0.01f;

/// A new shading frame around n, keeping the old tangent's direction where it can.
Frame frameAround(const Vector3f &n, const Vector3f &tangent) {
    Vector3f s = tangent - n * n.dot(tangent);
    if (s.squaredNorm() < 1e-12f)
        return Frame(n);
    s.normalize();
    return Frame(s, n.cross(s), n);
}

} // namespace

bool Shape::usesFootprint() const {
    auto anyFiltered = [](const TextureParameters &parameters) {
        for (const auto &texture : parameters.all())
            if (texture->usesFootprint())
                return true;
        return false;
    };
    return m_bumpMap || (m_normalMap && m_normalMap->usesFootprint()) ||
           (m_bsdf && anyFiltered(m_bsdf->textures())) ||
           (m_emitter && anyFiltered(m_emitter->textures()));
}

void Shape::completeHit(const Ray3f &ray, Intersection &its) const {
    if (m_uvScale != Vector2f(1.0f, 1.0f)) {
        // u' = su·u: dp/du' = (dp/du)/su, and likewise for v and the normal's derivatives.
        its.uv = textureUV(its.uv);
        its.dpdu /= m_uvScale.x();
        its.dpdv /= m_uvScale.y();
        its.dndu /= m_uvScale.x();
        its.dndv /= m_uvScale.y();
    }
    computeDifferentials(its, ray);
    if (!m_normalMap && !m_bumpMap)
        return;

    const Vector3f ns = its.shFrame.n;
    Vector3f n;
    if (m_normalMap) {
        // Tangent space: the shading frame's s (along dp/du, or the mesh's per-vertex
        // tangent), t = n × s turned to follow dp/dv (mirrored uv), n. Stored as 2c − 1.
        const Color3f c = m_normalMap->eval(TextureQuery(its));
        const Vector3f local(2.0f * c.r() - 1.0f, 2.0f * c.g() - 1.0f, 2.0f * c.b() - 1.0f);
        const Vector3f s = its.shFrame.s;
        Vector3f t = ns.cross(s);
        if (t.dot(its.dpdv) < 0.0f)
            t = -t;
        n = local.x() * s + local.y() * t + local.z() * ns;
    } else {
        // Bump mapping (Blinn 1978; pbrt-v3 §9.3): displace p along n by h(u, v) and
        // differentiate by finite differences over half the pixel footprint.
        TextureQuery q(its);
        float du = 0.5f * (std::abs(its.dudx) + std::abs(its.dudy));
        float dv = 0.5f * (std::abs(its.dvdx) + std::abs(its.dvdy));
        if (du == 0.0f)
            du = 5e-4f;
        if (dv == 0.0f)
            dv = 5e-4f;
        const float h = m_bumpScale * m_bumpMap->evalFloat(q);
        q.uv = its.uv + Point2f(du, 0.0f);
        const float hu = m_bumpScale * m_bumpMap->evalFloat(q);
        q.uv = its.uv + Point2f(0.0f, dv);
        const float hv = m_bumpScale * m_bumpMap->evalFloat(q);
        const Vector3f dpdu = its.dpdu + (hu - h) / du * ns + h * its.dndu;
        const Vector3f dpdv = its.dpdv + (hv - h) / dv * ns + h * its.dndv;
        n = dpdu.cross(dpdv);
        if (n.dot(ns) < 0.0f)
            n = -n;
    }
    if (!(n.squaredNorm() > 0.0f) || !n.allFinite())
        return; // a zero or broken texel: keep the unperturbed frame
    n.normalize();

    // A perturbed normal can turn away from the viewer: the surface would then look at
    // its own back. Bend it toward the viewer until cos θ ≥ kMinShadingCosine, on the
    // viewer's (geometric) side; sidesAgree() then guards light arriving from below.
    const Vector3f wi = -ray.d.normalized();
    const float side = its.geoFrame.n.dot(wi) >= 0.0f ? 1.0f : -1.0f;
    const float cosine = side * n.dot(wi);
    if (cosine < kMinShadingCosine)
        n = (n + (kMinShadingCosine - cosine) * side * wi).normalized();
    its.shFrame = frameAround(n, its.shFrame.s);
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

void Shape::copySurfaceParameters(const Shape &other) {
    m_uvScale = other.m_uvScale;
    m_normalMap = other.m_normalMap;
    m_bumpMap = other.m_bumpMap;
    m_bumpScale = other.m_bumpScale;
}

void Shape::addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) {
    if (child->getClassType() == EBSDF) {
        setUniqueChild(m_bsdf, child, "a shape");
    } else if (child->getClassType() == EEmitter) {
        setUniqueChild(m_emitter, child, "a shape");
        m_emitter->setShape(this);
    } else if (child->getClassType() == EMedium) {
        if (name != "interior" && name != "exterior")
            throw NoriException("a shape's medium is named \"interior\" or \"exterior\", not "
                                "\"{}\"",
                                name);
        setUniqueChild(name == "interior" ? m_interior : m_exterior, child,
                       name == "interior" ? "a shape's interior" : "a shape's exterior");
    } else if (const auto *tmesh = dynamic_cast<const TMesh *>(child.get())) {
        if (!m_tmeshes)
            m_tmeshes = std::make_shared<TMeshSet>(*this);
        m_tmeshes->add(*tmesh);
    } else if (child->getClassType() == EMesh) {
        throw NoriException("a shape holds no other shapes, only <mesh type=\"tmesh\"> copies of "
                            "itself; put <{} type=\"{}\"> beside it",
                            classTypeName(child->getClassType()), child->pluginName());
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
        m_bsdf = createDefault<BSDF>(hasMediumInterface() ? "null" : "diffuse");
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
    if (!m_visible && m_emitter)
        throw NoriException("an invisible shape (visible = false) cannot carry an area light");
}

} // namespace nori
