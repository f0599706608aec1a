/*
 * area — a diffuse area light: radiance (constant or textured over the shape's uv)
 * leaving the front side of the shape it is nested in: the side its vertex normals
 * point to (as Nori 2 and pbrt decide, even when the triangles wind the other way),
 * else the side of its winding's normal; or both sides, each with that radiance, when
 * `twoSided` (pbrt-v4's `twosided` diffuse area light, whose power is then doubled).
 * Points are sampled in solid angle where the shape can: a sphere through the cone it
 * subtends, a mesh of at most 8 triangles in its spherical triangles (Arvo 1995; PBR 4th
 * ed. §6.5.4) when the shading point is within twice its bounding radius and no triangle
 * is nearly a point or nearly a hemisphere as seen from it: uniformly, or, where the
 * integrator gives the shading normal (the path tracers, volpath at surfaces, direct),
 * warped bilinearly by the cosines of each triangle's corners to it, so that directions
 * of large cos θ come more often (pbrt-v4's warp product sampling); otherwise, and other
 * meshes, by area. `sampling="area"` samples every shape by area (Nori 2's way), for
 * comparisons. Photons leave a point uniform by area in a cosine-weighted direction (on
 * either side with probability ½ when two-sided).
 *
 * Parameters:
 *   radiance  color/texture  (required)    emitted radiance
 *   sampling  string         (solidangle)  solidangle or area: how points are sampled
 *   twoSided  boolean        false         emit from both sides
 *
 *   <mesh type="obj"><string name="filename" value="scenes/cbox/meshes/light.obj"/>
 *       <emitter type="area"><color name="radiance" value="10, 10, 10"/></emitter></mesh>
 *
 *   <mesh type="sphere"><float name="radius" value="0.5"/>
 *       <emitter type="area"><color name="radiance" value="2"/></emitter></mesh>
 *
 *   <mesh type="obj"><string name="filename" value="scenes/cbox/meshes/light.obj"/>
 *       <emitter type="area"><color name="radiance" value="1"/>
 *           <string name="sampling" value="area"/></emitter></mesh>
 *
 *   <mesh type="rectangle"><transform name="toWorld"><scale value="0.5, 0.3, 1"/>
 *       <rotate axis="1, 0, 0" angle="70"/></transform>
 *       <emitter type="area"><color name="radiance" value="3"/></emitter></mesh>
 *
 *   <mesh type="disk"><transform name="toWorld"><scale value="0.4"/>
 *       <rotate axis="0, 1, 1" angle="40"/></transform>
 *       <emitter type="area"><color name="radiance" value="3"/></emitter></mesh>
 *
 *   <mesh type="rectangle"><transform name="toWorld"><rotate axis="1, 0, 0" angle="30"/>
 *       </transform><emitter type="area"><color name="radiance" value="1, 2, 3"/>
 *           <boolean name="twoSided" value="true"/></emitter></mesh>
 *
 *   <mesh type="cube"><transform name="toWorld"><scale value="0.2, 0.3, 0.1"/></transform>
 *       <emitter type="area"><color name="radiance" value="1"/></emitter></mesh>
 */
#include <nori/emitter.h>
#include <nori/frame.h>
#include <nori/rayerror.h>
#include <nori/shading.h>
#include <nori/shape.h>
#include <nori/warp.h>

#include <algorithm>
#include <cmath>

namespace nori {
namespace {

class AreaLight : public Emitter {
public:
    explicit AreaLight(const PropertyList &props) {
        m_radiance = m_textures.color(props, "radiance");
        if (m_radiance->isConstant() && (m_radiance->average() < 0.0f).any())
            throw NoriException("area: 'radiance' must not be negative");
        const std::string sampling = props.getString("sampling", "solidangle");
        if (sampling != "solidangle" && sampling != "area")
            throw NoriException("area: 'sampling' is \"{}\"; it must be \"solidangle\" or "
                                "\"area\"",
                                sampling);
        m_byArea = sampling == "area";
        m_twoSided = props.getBoolean("twoSided", false);
    }

    bool requiresShape() const override { return true; }

    Color3f sample(EmitterQueryRecord &lRec, const Point2f &sample) const override {
        // Behind a one-sided light (a Cornell box's ceiling, say) nothing needs sampling.
        if (!m_twoSided && m_shape->facesAwayFrom(lRec.ref))
            return Color3f(0.0f);
        const ShapeSample point =
            m_byArea ? m_shape->areaSampleFromReference(lRec.ref, sample)
                     : m_shape->sampleFromReference(lRec.ref, lRec.refNormal, sample);
        lRec.p = point.p;
        lRec.n = point.n;
        lRec.primitive = point.primitive;
        lRec.uv = textureUV(*m_shape, point.uv);
        const Vector3f toLight = lRec.p - lRec.ref;
        const float distance = toLight.norm();
        if (distance == 0.0f || point.pdf <= 0.0f)
            return Color3f(0.0f);
        lRec.wi = toLight / distance;
        lRec.pdf = point.pdf;
        lRec.setShadowRay(distance);
        const Color3f radiance = eval(lRec);
        return (radiance == 0.0f).all() ? radiance : Color3f(radiance / lRec.pdf);
    }

    Color3f eval(const EmitterQueryRecord &lRec) const override {
        // One-sided: only the side the normal points to emits; and only where the surface
        // is (an alpha-masked light, decided per point as ray hits decide it).
        if (!emitsToward(lRec))
            return Color3f(0.0f);
        if (const SurfaceOpacity *opacity = m_shape->getOpacity())
            if (!surfacePresent(opacity->opacityAt(lRec.uv, lRec.p), lRec.p))
                return Color3f(0.0f);
        return m_radiance->eval(lRec).max(0.0f);
    }

    float pdf(const EmitterQueryRecord &lRec) const override {
        if (!emitsToward(lRec))
            return 0.0f;
        return m_byArea ? m_shape->areaPdfFromReference(lRec.ref, lRec.p, lRec.n)
                        : solidAngleDensity(lRec);
    }

    // A point uniform by area (pdf_A = 1/A for meshes) and a cosine-weighted direction
    // about its normal (pdf_ω = cos θ/π): the weight Le·cos θ/(pdf_A·pdf_ω) = π·Le/pdf_A.
    // Two-sided, the side is chosen first with probability ½ (x of the direction sample,
    // stretched back to [0, 1)), which halves pdf_ω and doubles the weight.
    Color3f sampleEmission(EmissionSample &emission, const Point2f &positionSample,
                           const Point2f &directionSample) const override {
        const ShapeSample point = m_shape->sampleSurface(positionSample);
        if (point.pdf <= 0.0f)
            return Color3f(0.0f);
        Point2f hemisphereSample = directionSample;
        Normal3f side = point.n;
        if (m_twoSided) {
            const bool back = hemisphereSample.x() >= 0.5f;
            hemisphereSample.x() = std::min(2.0f * hemisphereSample.x() - (back ? 1.0f : 0.0f),
                                            std::nextafter(1.0f, 0.0f));
            if (back)
                side = -side;
        }
        const Vector3f local = Warp::squareToCosineHemisphere(hemisphereSample);
        const Vector3f direction = Frame(side).toWorld(local);
        const float sides = m_twoSided ? 2.0f : 1.0f;
        emission.p = point.p;
        emission.n = point.n;
        emission.density = {point.pdf, Warp::squareToCosineHemispherePdf(local) / sides};
        EmitterQueryRecord lRec;
        lRec.p = point.p;
        lRec.n = point.n;
        lRec.uv = textureUV(*m_shape, point.uv);
        // The sampled point carries the rounding of interpolating the shape's vertices:
        // bound it by the shape's extent (PBR 4th ed. §6.8.5) and leave past it.
        const BoundingBox3f &box = m_shape->getBoundingBox();
        const Vector3f pError = gammaBound(16) * box.min.cwiseAbs().cwiseMax(box.max.cwiseAbs());
        emission.ray =
            Ray3f(offsetRayOrigin(point.p, pError, side, direction), direction, 0.0f, kInfinity);
        return m_radiance->eval(lRec).max(0.0f) * (sides * kPi / point.pdf);
    }

    EmissionDensity emissionDensity(const Point3f &, const Normal3f &n,
                                    const Vector3f &direction) const override {
        const float cosTheta = n.dot(direction);
        return {1.0f / m_shape->getArea(), m_twoSided ? 0.5f * std::abs(cosTheta) * kInvPi
                                                      : std::max(0.0f, cosTheta) * kInvPi};
    }

    // A Lambertian emitter radiates π·L per unit area, from each side it emits from; a
    // texture by its uv average (exact when uv is proportional to area, a fair guess for
    // choosing lights otherwise).
    Color3f getPower() const override {
        return m_radiance->average().max(0.0f) *
               ((m_twoSided ? 2.0f : 1.0f) * kPi * m_shape->getArea());
    }

    // The shape's box and the cone of its normals, from which it emits up to 90°.
    std::optional<LightBounds> lightBounds() const override {
        const DirectionCone normals = m_shape->normalBounds();
        LightBounds bounds;
        bounds.bounds = m_shape->getBoundingBox();
        bounds.w = normals.w;
        bounds.cosThetaO = normals.cosTheta;
        bounds.cosThetaE = 0.0f;
        bounds.twoSided = m_twoSided;
        bounds.phi = getPower().getLuminance();
        return bounds;
    }

    std::string toString() const override {
        return fmt::format("AreaLight[radiance={}, sampling={}, twoSided={}]",
                           m_radiance->toString(), m_byArea ? "area" : "solidangle", m_twoSided);
    }

private:
    /// Whether light leaves the surface toward the record's reference point: toward the
    /// normal's side, or either side when two-sided.
    bool emitsToward(const EmitterQueryRecord &lRec) const {
        return m_twoSided ? lRec.n.dot(lRec.wi) != 0.0f : lRec.n.dot(lRec.wi) < 0.0f;
    }

    /// The density sampleFromReference has for the record's point, on the primitive the
    /// record names (a ray hit's, a sample's).
    float solidAngleDensity(const EmitterQueryRecord &lRec) const {
        ShapeSample point;
        point.p = lRec.p;
        point.n = lRec.n;
        point.primitive = lRec.primitive;
        return m_shape->pdfFromReference(lRec.ref, lRec.refNormal, point);
    }

    std::shared_ptr<const Texture> m_radiance;
    bool m_byArea = false;   ///< sample points uniformly by area, not in solid angle
    bool m_twoSided = false; ///< emits from both sides
};

NORI_REGISTER_CLASS(AreaLight, "area");

} // namespace
} // namespace nori
