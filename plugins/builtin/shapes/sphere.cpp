/*
 * sphere — an analytic sphere. uv as the courses define them: with n the unit normal,
 * φ = atan2(n.y, n.x) around +z and θ = acos(n.z) from +z, v = 1 − θ/π runs from the
 * south pole (v = 0) to the north pole (v = 1), and u = ½ + φ/2π in [0, 1] (Nori 2's
 * and EPFL's convention, the default) or u = φ/2π in [−½, ½] (ETH's 2024 course).
 * Mitsuba's (0.6 and 3) are u = φ/2π in [0, 1) (φ + 2π where negative) and v = θ/π,
 * from the north pole down.
 *
 * As an area light it is sampled through the cone of directions it subtends
 * (PBR 4th ed. §6.2.4) when the reference point is outside, by area otherwise.
 *
 * Parameters:
 *   center       point    (0, 0, 0)  centre of the sphere
 *   radius       float    1          radius, positive
 *   flipNormals  boolean  false      normals point inward (a room, or an emitting shell
 *                                    lit from inside)
 *   uvScale      vector   (1, 1)     uv are scaled by this for textures (a <float>
 *                                    scales both)
 *   convention   string   "epfl"     "epfl": u in [0, 1]; "eth": u in [−½, ½]; see
 *                                    nori --convention; "mitsuba": Mitsuba's uv
 *   normal       texture  —          tangent-space normal map (decoded as 2c − 1)
 *   bump         texture  —          height map for bump mapping (instead of normal)
 *   bumpScale    float    1          the heights are scaled by this
 *   visible      boolean  true       false: the shape is only a template that its
 *                                    tmesh children copy
 *
 *   <mesh type="sphere">
 *       <point name="center" value="0, 1, 0"/> <float name="radius" value="0.5"/>
 *   </mesh>
 */
#include <nori/convention.h>
#include <nori/rayerror.h>
#include <nori/shading.h>
#include <nori/shape.h>
#include <nori/warp.h>

namespace nori {
namespace {

class Sphere : public Shape {
public:
    explicit Sphere(const PropertyList &props) {
        m_center = props.getPoint("center", Point3f(0.0f));
        m_radius = props.getFloat("radius", 1.0f);
        m_flipNormals = props.getBoolean("flipNormals", false);
        if (props.has("convention") && props.getString("convention") == "mitsuba")
            m_mitsubaUV = true;
        else
            m_uOffset = readCourseConvention(props) == CourseConvention::EPFL ? 0.5f : 0.0f;
        readSurfaceParameters(*this, props);
        if (!(m_radius > 0.0f) || !std::isfinite(m_radius))
            throw NoriException("sphere: 'radius' must be positive, got {}", m_radius);
        m_bbox = BoundingBox3f(m_center - Vector3f(m_radius), m_center + Vector3f(m_radius));
    }

    uint32_t getPrimitiveCount() const override { return 1; }
    BoundingBox3f getPrimitiveBoundingBox(uint32_t) const override { return m_bbox; }
    Point3f getPrimitiveCentroid(uint32_t) const override { return m_center; }

    bool rayIntersect(uint32_t, const Ray3f &ray, float &t, Point2f &hitCoords) const override {
        // |o + t d − c|² = r²; the discriminant in the form of PBR 4th ed. §6.8.1,
        // b² − 4ac = 4a(r² − |f − (f·d̂)d̂|²) with f = o − c, which avoids cancellation.
        const Vector3f f = ray.o - m_center;
        const float a = ray.d.squaredNorm();
        const float b = 2.0f * f.dot(ray.d);
        const Vector3f perpendicular = f - (f.dot(ray.d) / a) * ray.d;
        const float discriminant = 4.0f * a * (m_radius * m_radius - perpendicular.squaredNorm());
        if (discriminant < 0.0f)
            return false;
        const float rootDiscriminant = std::sqrt(discriminant);
        const float q = b < 0.0f ? -0.5f * (b - rootDiscriminant) : -0.5f * (b + rootDiscriminant);
        if (q == 0.0f)
            return false;
        float t0 = q / a, t1 = (f.squaredNorm() - m_radius * m_radius) / q; // c/q
        if (t0 > t1)
            std::swap(t0, t1);
        if (t0 >= ray.mint && t0 <= ray.maxt)
            t = t0;
        else if (t1 >= ray.mint && t1 <= ray.maxt)
            t = t1;
        else
            return false;
        hitCoords = Point2f(0.0f, 0.0f);
        return true;
    }

    void setHitInformation(uint32_t, const Ray3f &ray, const Point2f &,
                           Intersection &its) const override {
        const Vector3f n = Vector3f(ray(its.t) - m_center).normalized();
        const float side = m_flipNormals ? -1.0f : 1.0f;
        // Project back onto the surface to remove the error of o + t·d; what remains is
        // the rounding of c + r·n (PBR 4th ed. §6.8.5 bounds it by γ₅|p| for a sphere).
        its.p = m_center + m_radius * n;
        its.pError = gammaBound(5) * Vector3f(m_center.cwiseAbs() + (m_radius * n).cwiseAbs());
        its.primIndex = 0;
        its.shape = its.mesh = this;

        its.uv = uvOf(n);
        const float phi = std::atan2(n.y(), n.x());
        const float sinBeta = std::clamp(n.z(), -1.0f, 1.0f);
        const float cosBeta = safeSqrt(1.0f - sinBeta * sinBeta);

        // p = c + r (cos β cos φ, cos β sin φ, sin β), with φ = 2π(u − ½), β = π(v − ½):
        // ∂p/∂u = 2π r (−cos β sin φ, cos β cos φ, 0); ∂p/∂v = π r (−sin β cos φ, −sin β sin φ, cos
        // β).
        const float sinPhi = std::sin(phi), cosPhi = std::cos(phi);
        its.dpdu = 2.0f * kPi * m_radius * Vector3f(-cosBeta * sinPhi, cosBeta * cosPhi, 0.0f);
        its.dpdv = kPi * m_radius * Vector3f(-sinBeta * cosPhi, -sinBeta * sinPhi, cosBeta);
        if (m_mitsubaUV) // v = θ/π runs the other way
            its.dpdv = -its.dpdv;

        // Tangent along ∂p/∂u where it exists (not at the poles).
        const Vector3f normal = side * n;
        if (its.dpdu.squaredNorm() > 1e-12f) {
            const Vector3f s = its.dpdu.normalized();
            its.geoFrame = Frame(s, normal.cross(s), normal);
        } else {
            its.geoFrame = Frame(normal);
        }
        its.shFrame = its.geoFrame;
        // n = ±(p − c)/r, so dn/du = ±(dp/du)/r.
        its.dndu = side / m_radius * its.dpdu;
        its.dndv = side / m_radius * its.dpdv;
    }

    float getArea() const override { return 4.0f * kPi * m_radius * m_radius; }

    ShapeSample sampleSurface(const Point2f &sample) const override {
        const Vector3f n = Warp::squareToUniformSphere(sample);
        ShapeSample result;
        result.p = m_center + m_radius * n;
        result.n = m_flipNormals ? Vector3f(-n) : n;
        result.uv = uvOf(n);
        result.pdf = 1.0f / getArea();
        return result;
    }

    ShapeSample sampleFromReference(const Point3f &ref, const Normal3f &,
                                    const Point2f &sample) const override {
        const Vector3f toCenter = m_center - ref;
        const float distanceSquared = toCenter.squaredNorm();
        if (!seesCone(distanceSquared))
            return areaSampleFromReference(ref, sample);
        // A uniform direction in the cone the sphere subtends, then the nearer point
        // where that direction meets the sphere.
        const float distance = std::sqrt(distanceSquared);
        const float cosThetaMax = safeSqrt(1.0f - m_radius * m_radius / distanceSquared);
        const Vector3f local = Warp::squareToUniformSphereCap(sample, cosThetaMax);
        const Vector3f direction = Frame(Vector3f(toCenter / distance)).toWorld(local);
        // |ref + t·d − c| = r, nearer root: t = d·(c − ref) − √(r² − |perpendicular|²).
        const float along = direction.dot(toCenter);
        const float perpendicular2 = std::max(0.0f, distanceSquared - along * along);
        const float t = along - safeSqrt(m_radius * m_radius - perpendicular2);
        ShapeSample result;
        result.p = ref + t * direction;
        const Vector3f n = Vector3f(result.p - m_center).normalized();
        result.n = m_flipNormals ? Vector3f(-n) : n;
        result.uv = uvOf(n);
        result.pdf = Warp::squareToUniformSphereCapPdf(local, cosThetaMax);
        return result;
    }

    float pdfFromReference(const Point3f &ref, const Normal3f &,
                           const ShapeSample &point) const override {
        const Vector3f toCenter = m_center - ref;
        const float distanceSquared = toCenter.squaredNorm();
        if (!seesCone(distanceSquared))
            return areaPdfFromReference(ref, point.p, point.n);
        // Only the near side is in the cone: the far side is never sampled.
        if (Vector3f(point.p - m_center).dot(Vector3f(ref - m_center)) < 0.0f)
            return 0.0f;
        const float cosThetaMax = safeSqrt(1.0f - m_radius * m_radius / distanceSquared);
        return kInvTwoPi / (1.0f - cosThetaMax);
    }

    std::string toString() const override {
        return fmt::format("Sphere[center=({}, {}, {}), radius={}, flipNormals={}, convention={}]",
                           m_center.x(), m_center.y(), m_center.z(), m_radius, m_flipNormals,
                           m_mitsubaUV         ? "mitsuba"
                           : m_uOffset == 0.0f ? "eth"
                                               : "epfl");
    }

private:
    /// uv of the unit outward direction n: u = offset + φ/2π, v = 1 − θ/π, computed as
    /// the courses do, so that a pole is hit exactly (v = 1 at n = +z: uvtexture's
    /// |fmod(v, 1)| is then 0, as the course's references expect).
    /// Mitsuba's: u = φ/2π with φ in [0, 2π), v = θ/π (Mitsuba 0.6 and 3, sphere).
    Point2f uvOf(const Vector3f &n) const {
        const float phi = std::atan2(n.y(), n.x());
        const float theta = std::acos(std::clamp(n.z(), -1.0f, 1.0f));
        if (m_mitsubaUV)
            return Point2f((phi < 0.0f ? phi + 2.0f * kPi : phi) * kInvTwoPi, theta * kInvPi);
        return Point2f(m_uOffset + phi * kInvTwoPi, 1.0f - theta * kInvPi);
    }

    /// Whether a reference point at this squared distance from the centre is clearly
    /// outside, so the sphere subtends a proper cone; points inside or on the surface
    /// (within a relative 1e-3, e.g. on the light itself) use area sampling.
    bool seesCone(float distanceSquared) const {
        return distanceSquared > m_radius * m_radius * (1.0f + 1e-3f);
    }

    Point3f m_center;
    float m_radius;
    bool m_flipNormals;
    float m_uOffset = 0.5f;   ///< ½ (EPFL: u in [0, 1]) or 0 (ETH: u in [−½, ½])
    bool m_mitsubaUV = false; ///< Mitsuba's uv instead
};

NORI_REGISTER_CLASS(Sphere, "sphere");

} // namespace
} // namespace nori
