#include <nori/bsdf.h>
#include <nori/emitter.h>
#include <nori/proplist.h>
#include <nori/raydifferential.h>
#include <nori/shading.h>
#include <nori/texture.h>

namespace nori {

std::shared_ptr<const SurfaceShading> SurfaceShading::read(const PropertyList &props) {
    auto shading = std::make_shared<SurfaceShading>();
    shading->m_uvScale = props.holdsScalar("uvScale")
                             ? Vector2f::Constant(props.getFloat("uvScale"))
                             : props.getVector2("uvScale", Vector2f(1.0f, 1.0f));
    if (!(shading->m_uvScale.allFinite() && shading->m_uvScale.x() != 0.0f &&
          shading->m_uvScale.y() != 0.0f))
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
    shading->m_normalMap = dataTexture("normal");
    shading->m_bumpMap = dataTexture("bump");
    shading->m_bumpScale = props.getFloat("bumpScale", 1.0f);
    if (shading->m_normalMap && shading->m_bumpMap)
        throw NoriException("give a 'normal' map or a 'bump' map, not both");
    if (!std::isfinite(shading->m_bumpScale))
        throw NoriException("'bumpScale' must be finite");
    if (shading->m_uvScale == Vector2f(1.0f, 1.0f) && !shading->m_normalMap && !shading->m_bumpMap)
        return nullptr;
    return shading;
}

std::shared_ptr<const SurfaceShading>
SurfaceShading::withBumpMap(const SurfaceShading *base, std::shared_ptr<const Texture> heights,
                            float scale) {
    auto shading =
        base ? std::make_shared<SurfaceShading>(*base) : std::make_shared<SurfaceShading>();
    if (shading->m_normalMap || shading->m_bumpMap)
        throw NoriException("the shape has a normal or bump map already");
    if (!std::isfinite(scale))
        throw NoriException("a bump map's scale must be finite");
    // Heights are data: 8-bit images are not sRGB-decoded.
    auto linear = heights->linearVariant();
    shading->m_bumpMap = linear ? linear : std::move(heights);
    shading->m_bumpScale = scale;
    return shading;
}

namespace {

/// Smallest cosine between the viewer and a perturbed shading normal (see perturbNormal).
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

void SurfaceShading::scaleUV(Intersection &its) const {
    if (m_uvScale == Vector2f(1.0f, 1.0f))
        return;
    // u' = su·u: dp/du' = (dp/du)/su, and likewise for v and the normal's derivatives.
    its.uv = textureUV(its.uv);
    its.dpdu /= m_uvScale.x();
    its.dpdv /= m_uvScale.y();
    its.dndu /= m_uvScale.x();
    its.dndv /= m_uvScale.y();
}

void SurfaceShading::perturbNormal(const Ray3f &ray, Intersection &its) const {
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

bool SurfaceShading::usesFootprint() const {
    return m_bumpMap || (m_normalMap && m_normalMap->usesFootprint());
}

AlphaMask::AlphaMask(std::shared_ptr<const Texture> opacity, const Shape &shape)
    : m_opacity(std::move(opacity)), m_shape(shape) {}

float AlphaMask::opacityAtHit(const Point2f &shapeUV, const Point3f &p) const {
    return opacityAt(textureUV(m_shape, shapeUV), p);
}

float AlphaMask::opacityAt(const Point2f &textureUV, const Point3f &p) const {
    TextureQuery q(textureUV);
    q.p = p;
    return m_opacity->evalFloat(q);
}

void readSurfaceParameters(Shape &shape, const PropertyList &props) {
    shape.setVisible(props.getBoolean("visible", true));
    shape.setSurfaceShading(SurfaceShading::read(props));
    if (props.holdsObject("alpha")) {
        auto texture = std::dynamic_pointer_cast<const Texture>(props.getObject("alpha"));
        if (!texture)
            throw NoriException("'alpha' must be a float or a <texture name=\"alpha\">");
        // An opacity is data: 8-bit images are not sRGB-decoded.
        auto linear = texture->linearVariant();
        shape.setOpacity(std::make_shared<AlphaMask>(linear ? linear : texture, shape));
    } else if (props.has("alpha")) {
        const float alpha = props.getFloat("alpha");
        if (!(alpha >= 0.0f && alpha <= 1.0f))
            throw NoriException("'alpha' must lie in [0, 1], got {}", alpha);
        if (alpha < 1.0f)
            shape.setOpacity(
                std::make_shared<AlphaMask>(makeConstantTexture(Color3f(alpha)), shape));
    }
}

void completeHit(const Ray3f &ray, Intersection &its) {
    const SurfaceShading *shading = its.shape->getSurfaceShading();
    if (shading)
        shading->scaleUV(its);
    computeDifferentials(its, ray);
    if (shading)
        shading->perturbNormal(ray, its);
}

Point2f textureUV(const Shape &shape, const Point2f &uv) {
    const SurfaceShading *shading = shape.getSurfaceShading();
    return shading ? shading->textureUV(uv) : uv;
}

bool usesFootprint(const Shape &shape) {
    auto anyFiltered = [](const TextureParameters &parameters) {
        for (const auto &texture : parameters.all())
            if (texture->usesFootprint())
                return true;
        return false;
    };
    const SurfaceShading *shading = shape.getSurfaceShading();
    return (shading && shading->usesFootprint()) ||
           (shape.getBSDF() && anyFiltered(shape.getBSDF()->textures())) ||
           (shape.getEmitter() && anyFiltered(shape.getEmitter()->textures()));
}

} // namespace nori
