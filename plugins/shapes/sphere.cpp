/*
 * sphere — an analytic sphere. uv are spherical coordinates: u = φ/2π around +z,
 * v = θ/π from +z.
 *
 * Parameters:
 *   center  point  (0, 0, 0)  centre of the sphere
 *   radius  float  1          radius, positive
 *
 *   <mesh type="sphere">
 *       <point name="center" value="0, 1, 0"/> <float name="radius" value="0.5"/>
 *   </mesh>
 */
#include <nori/rayerror.h>
#include <nori/shape.h>

namespace nori {

class Sphere : public Shape {
public:
    explicit Sphere(const PropertyList &props) {
        m_center = props.getPoint("center", Point3f(0.0f));
        m_radius = props.getFloat("radius", 1.0f);
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
        // Project back onto the surface to remove the error of o + t·d; what remains is
        // the rounding of c + r·n (PBR 4th ed. §6.8.5 bounds it by γ₅|p| for a sphere).
        its.p = m_center + m_radius * n;
        its.pError = gammaBound(5) * Vector3f(m_center.cwiseAbs() + (m_radius * n).cwiseAbs());
        its.primIndex = 0;
        its.shape = this;

        const float phi = std::atan2(n.y(), n.x());
        const float theta = std::acos(std::clamp(n.z(), -1.0f, 1.0f));
        its.uv = Point2f((phi < 0.0f ? phi + 2.0f * kPi : phi) * kInvTwoPi, theta * kInvPi);

        // ∂p/∂u = 2π r (−sinθ sinφ, sinθ cosφ, 0); ∂p/∂v = π r (cosθ cosφ, cosθ sinφ, −sinθ).
        const float sinTheta = std::sin(theta), cosTheta = std::cos(theta);
        its.dpdu = 2.0f * kPi * m_radius *
                   Vector3f(-sinTheta * std::sin(phi), sinTheta * std::cos(phi), 0.0f);
        its.dpdv = kPi * m_radius *
                   Vector3f(cosTheta * std::cos(phi), cosTheta * std::sin(phi), -sinTheta);

        // Tangent along ∂p/∂u where it exists (not at the poles).
        if (its.dpdu.squaredNorm() > 1e-12f) {
            const Vector3f s = its.dpdu.normalized();
            its.geoFrame = Frame(s, n.cross(s), n);
        } else {
            its.geoFrame = Frame(n);
        }
        its.shFrame = its.geoFrame;
    }

    std::string toString() const override {
        return fmt::format("Sphere[center=({}, {}, {}), radius={}]", m_center.x(), m_center.y(),
                           m_center.z(), m_radius);
    }

private:
    Point3f m_center;
    float m_radius;
};

NORI_REGISTER_CLASS(Sphere, "sphere");

} // namespace nori
