/*
 * cylinder — an open tube (no caps) of radius `radius` around the segment from p0 to p1,
 * placed by `toWorld` (Mitsuba 0.6 documentation, "cylinder"): an analytic shape, seen
 * from inside and outside, normals outward. uv = (φ/2π, h) with φ the angle about the
 * axis and h from 0 at p0 to 1 at p1. As an area light it is sampled uniformly by area
 * (φ and h uniform: the tube unrolls to a rectangle). `toWorld` may rotate, translate and
 * scale, but must keep the cross-section a circle (no shear, the same scale across the
 * axis), as Mitsuba requires.
 *
 * Parameters:
 *   p0           point      (0, 0, 0)  centre of one end
 *   p1           point      (0, 0, 1)  centre of the other end
 *   radius       float      1          radius, positive
 *   toWorld      transform  identity   object-to-world transform, applied after p0, p1
 *   flipNormals  boolean    false      normals point inward
 *   uvScale      vector     (1, 1)     uv are scaled by this for textures
 *   normal       texture    —          tangent-space normal map
 *   bump         texture    —          height map for bump mapping
 *   bumpScale    float      1          the heights are scaled by this
 *   visible      boolean    true       false: only a template for tmesh copies
 *
 *   <mesh type="cylinder">
 *       <point name="p0" value="0, -0.5, 0"/> <point name="p1" value="0, 0.5, 0"/>
 *       <float name="radius" value="0.2"/>
 *   </mesh>
 */
#include <nori/rayerror.h>
#include <nori/shading.h>
#include <nori/shape.h>

namespace nori {
namespace {

class Cylinder : public Shape {
public:
    explicit Cylinder(const PropertyList &props) {
        const Point3f p0 = props.getPoint("p0", Point3f(0, 0, 0));
        const Point3f p1 = props.getPoint("p1", Point3f(0, 0, 1));
        const float radius = props.getFloat("radius", 1.0f);
        const Transform toWorld = props.getTransform("toWorld", Transform());
        m_flipNormals = props.getBoolean("flipNormals", false);
        readSurfaceParameters(*this, props);
        if (!(radius > 0.0f) || !std::isfinite(radius))
            throw NoriException("cylinder: 'radius' must be positive, got {}", radius);
        const Vector3f localAxis = p1 - p0;
        if (!(localAxis.norm() > 0.0f))
            throw NoriException("cylinder: 'p0' and 'p1' must differ");
        // The tube in world space: the frame's two radial axes and the axis, mapped.
        const Frame local(Vector3f(localAxis.normalized()));
        const AffineMap map = AffineMap::of(toWorld.getMatrix());
        const Vector3f s = map.applyToVector(local.s * radius),
                       t = map.applyToVector(local.t * radius);
        const Vector3f axis = map.applyToVector(localAxis);
        const float tolerance = 1e-4f * (s.norm() + t.norm() + axis.norm());
        if (std::abs(s.norm() - t.norm()) > tolerance ||
            std::abs(s.dot(t)) > tolerance * s.norm() ||
            std::abs(s.dot(axis)) > tolerance * axis.norm() ||
            std::abs(t.dot(axis)) > tolerance * axis.norm())
            throw NoriException("cylinder: 'toWorld' must keep the cross-section a circle (no "
                                "shear, the same scale across the axis)");
        m_base = map.applyToPoint(p0);
        m_radius = s.norm();
        m_length = axis.norm();
        if (!(m_radius > 0.0f && m_length > 0.0f))
            throw NoriException("cylinder: 'toWorld' flattens the tube to nothing");
        m_frame = Frame(Vector3f(s / m_radius), Vector3f(t / m_radius), Vector3f(axis / m_length));
        // The box of the two end circles: a circle of normal a spans r√(1 − a_i²) along axis i.
        const Vector3f a = m_frame.n;
        const Vector3f extent =
            m_radius * (Vector3f(1, 1, 1) - a.cwiseProduct(a)).cwiseMax(0.0f).cwiseSqrt();
        m_bbox = BoundingBox3f(m_base - extent, m_base + extent);
        m_bbox.expandBy(BoundingBox3f(m_base + axis - extent, m_base + axis + extent));
    }

    uint32_t getPrimitiveCount() const override { return 1; }
    BoundingBox3f getPrimitiveBoundingBox(uint32_t) const override { return m_bbox; }
    Point3f getPrimitiveCentroid(uint32_t) const override { return m_bbox.getCenter(); }

    bool rayIntersect(uint32_t, const Ray3f &ray, float &t, Point2f &hitCoords) const override {
        // In the tube's frame: x² + y² = r² for o + t·d, and 0 ≤ z ≤ length. The
        // discriminant in the form of PBR 4th ed. §6.8.1 (as the sphere's).
        const Vector3f o = m_frame.toLocal(Vector3f(ray.o - m_base));
        const Vector3f d = m_frame.toLocal(ray.d);
        const float a = d.x() * d.x() + d.y() * d.y();
        if (a == 0.0f)
            return false; // along the axis: it never meets the wall
        const float b = 2.0f * (o.x() * d.x() + o.y() * d.y());
        const float c = o.x() * o.x() + o.y() * o.y() - m_radius * m_radius;
        const float along = (o.x() * d.x() + o.y() * d.y()) / a;
        const float px = o.x() - along * d.x(), py = o.y() - along * d.y();
        const float discriminant = 4.0f * a * (m_radius * m_radius - (px * px + py * py));
        if (discriminant < 0.0f)
            return false;
        const float root = std::sqrt(discriminant);
        const float q = b < 0.0f ? -0.5f * (b - root) : -0.5f * (b + root);
        if (q == 0.0f)
            return false;
        float t0 = q / a, t1 = c / q;
        if (t0 > t1)
            std::swap(t0, t1);
        for (const float candidate : {t0, t1}) {
            if (candidate < ray.mint || candidate > ray.maxt)
                continue;
            const float z = o.z() + candidate * d.z();
            if (z < 0.0f || z > m_length)
                continue;
            t = candidate;
            hitCoords = Point2f(z, 0.0f);
            return true;
        }
        return false;
    }

    void setHitInformation(uint32_t, const Ray3f &ray, const Point2f &hitCoords,
                           Intersection &its) const override {
        const Vector3f local = m_frame.toLocal(Vector3f(ray(its.t) - m_base));
        float phi = std::atan2(local.y(), local.x());
        if (phi < 0.0f)
            phi += 2.0f * kPi;
        fillPoint(phi, hitCoords.x(), its);
    }

    float getArea() const override { return 2.0f * kPi * m_radius * m_length; }

    ShapeSample sampleSurface(const Point2f &sample) const override {
        Intersection its;
        fillPoint(2.0f * kPi * sample.x(), sample.y() * m_length, its);
        ShapeSample result;
        result.p = its.p;
        result.n = its.geoFrame.n;
        result.uv = its.uv;
        result.pdf = 1.0f / getArea();
        return result;
    }

    bool isClosed() const override { return false; }

    std::string toString() const override {
        return fmt::format("Cylinder[radius={}, length={}, flipNormals={}]", m_radius, m_length,
                           m_flipNormals);
    }

private:
    /// The hit record at angle φ about the axis and height z along it (projected onto the
    /// tube, so only the rounding of base + frame·(r cos φ, r sin φ, z) remains).
    void fillPoint(float phi, float z, Intersection &its) const {
        const float cosPhi = std::cos(phi), sinPhi = std::sin(phi);
        const Vector3f radial = m_frame.toWorld(Vector3f(cosPhi, sinPhi, 0.0f));
        const Vector3f along = m_frame.n * z;
        its.p = m_base + m_radius * radial + along;
        its.pError = gammaBound(6) *
                     Vector3f(m_base.cwiseAbs() + m_radius * radial.cwiseAbs() + along.cwiseAbs());
        its.primIndex = 0;
        its.shape = its.mesh = this;
        its.uv = Point2f(phi * kInvTwoPi, z / m_length);
        // p = base + r(cos φ s + sin φ t) + z a, with u = φ/2π and v = z/length.
        const Vector3f tangent = m_frame.toWorld(Vector3f(-sinPhi, cosPhi, 0.0f));
        its.dpdu = 2.0f * kPi * m_radius * tangent;
        its.dpdv = m_length * m_frame.n;
        const float side = m_flipNormals ? -1.0f : 1.0f;
        const Vector3f normal = side * radial;
        its.geoFrame = Frame(tangent, normal.cross(tangent), normal);
        its.shFrame = its.geoFrame;
        // n = ±(p − axis point)/r, so dn/du = ±(dp/du)/r and dn/dv = 0.
        its.dndu = side / m_radius * its.dpdu;
        its.dndv = Vector3f::Zero();
    }

    Point3f m_base;
    Frame m_frame; ///< s, t across the axis, n along it
    float m_radius, m_length;
    bool m_flipNormals;
};

NORI_REGISTER_CLASS(Cylinder, "cylinder");

} // namespace
} // namespace nori
