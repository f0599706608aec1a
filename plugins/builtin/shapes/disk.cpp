/*
 * disk — the unit disk in the plane z = 0, facing +z, placed by `toWorld` (Mitsuba 0.6
 * documentation, "disk"): an analytic shape, so its rim is a true circle (an ellipse
 * under a non-uniform scale). uv = (r, φ/2π) in polar coordinates about its centre, φ
 * from the local +x axis, as Mitsuba has them. As an area light, it is sampled uniformly
 * by area: an affine map scales every piece of a plane by the same factor, so a uniform
 * point of the unit disk (Shirley and Chiu's concentric map) stays uniform.
 *
 * Parameters:
 *   toWorld      transform  identity  object-to-world transform
 *   flipNormals  boolean    false     face −z instead
 *   uvScale      vector     (1, 1)    uv are scaled by this for textures
 *   normal       texture    —         tangent-space normal map
 *   bump         texture    —         height map for bump mapping
 *   bumpScale    float      1         the heights are scaled by this
 *   visible      boolean    true      false: only a template for tmesh copies
 *
 *   <mesh type="disk">
 *       <transform name="toWorld"><scale value="0.5"/> <rotate axis="1, 0, 0" angle="90"/></transform>
 *   </mesh>
 */
#include <nori/rayerror.h>
#include <nori/shading.h>
#include <nori/shape.h>
#include <nori/warp.h>

namespace nori {
namespace {

class Disk : public Shape {
public:
    explicit Disk(const PropertyList &props) {
        const Transform toWorld = props.getTransform("toWorld", Transform());
        m_flipNormals = props.getBoolean("flipNormals", false);
        readSurfaceParameters(*this, props);
        m_toWorld = AffineMap::of(toWorld.getMatrix());
        m_toLocal = m_toWorld.inverse();
        const Vector3f x = m_toWorld.applyToVector(Vector3f(1, 0, 0)),
                       y = m_toWorld.applyToVector(Vector3f(0, 1, 0));
        m_area = kPi * x.cross(y).norm();
        if (!(m_area > 0.0f) || !std::isfinite(m_area))
            throw NoriException("disk: 'toWorld' flattens the disk to nothing (area {})", m_area);
        m_normal = m_toLocal.applyTransposeToNormal(Vector3f(0, 0, 1)).normalized();
        if (m_flipNormals)
            m_normal = -m_normal;
        // The ellipse's box: the centre ± √(x_i² + y_i²) along each world axis.
        const Point3f center = m_toWorld.applyToPoint(Point3f(0, 0, 0));
        const Vector3f extent = (x.cwiseProduct(x) + y.cwiseProduct(y)).cwiseSqrt();
        m_bbox = BoundingBox3f(center - extent, center + extent);
    }

    uint32_t getPrimitiveCount() const override { return 1; }
    BoundingBox3f getPrimitiveBoundingBox(uint32_t) const override { return m_bbox; }
    Point3f getPrimitiveCentroid(uint32_t) const override { return m_bbox.getCenter(); }

    bool rayIntersect(uint32_t, const Ray3f &ray, float &t, Point2f &hitCoords) const override {
        // In the disk's space the plane is z = 0; t is the same in both spaces.
        const Point3f o = m_toLocal.applyToPoint(ray.o);
        const Vector3f d = m_toLocal.applyToVector(ray.d);
        if (d.z() == 0.0f)
            return false;
        const float tHit = -o.z() / d.z();
        if (!(tHit >= ray.mint && tHit <= ray.maxt))
            return false;
        const float x = o.x() + tHit * d.x(), y = o.y() + tHit * d.y();
        if (x * x + y * y > 1.0f)
            return false;
        t = tHit;
        hitCoords = Point2f(x, y);
        return true;
    }

    void setHitInformation(uint32_t, const Ray3f &, const Point2f &hitCoords,
                           Intersection &its) const override {
        fillPoint(hitCoords, its);
    }

    float getArea() const override { return m_area; }

    DirectionCone normalBounds() const override { return DirectionCone(m_normal, 1.0f); }

    bool facesAwayFrom(const Point3f &ref) const override {
        return m_normal.dot(ref - m_toWorld.applyToPoint(Point3f(0, 0, 0))) <= 0.0f;
    }

    ShapeSample sampleSurface(const Point2f &sample) const override {
        const Point2f local = Warp::squareToUniformDiskConcentric(sample);
        Intersection its;
        fillPoint(local, its);
        ShapeSample result;
        result.p = its.p;
        result.n = m_normal;
        result.uv = its.uv;
        result.pdf = 1.0f / m_area;
        return result;
    }

    std::string toString() const override {
        return fmt::format("Disk[area={}, flipNormals={}]", m_area, m_flipNormals);
    }

private:
    /// The hit record of the local point (x, y, 0).
    void fillPoint(const Point2f &local, Intersection &its) const {
        const Point3f p(local.x(), local.y(), 0.0f);
        its.p = m_toWorld.applyToPoint(p);
        its.pError = m_toWorld.roundingError(p) + gammaBound(5) * its.p.cwiseAbs();
        its.primIndex = 0;
        its.shape = its.mesh = this;
        const float r = std::sqrt(local.x() * local.x() + local.y() * local.y());
        float phi = std::atan2(local.y(), local.x());
        if (phi < 0.0f)
            phi += 2.0f * kPi;
        its.uv = Point2f(r, phi * kInvTwoPi);
        // p = A (r cos φ, r sin φ, 0) + b with u = r, v = φ/2π.
        const float cosPhi = std::cos(phi), sinPhi = std::sin(phi);
        its.dpdu = m_toWorld.applyToVector(Vector3f(cosPhi, sinPhi, 0.0f));
        its.dpdv = m_toWorld.applyToVector(Vector3f(-sinPhi, cosPhi, 0.0f) * (2.0f * kPi * r));
        const Vector3f tangent = its.dpdu - m_normal * m_normal.dot(its.dpdu);
        its.geoFrame =
            tangent.squaredNorm() > 1e-20f
                ? Frame(tangent.normalized(), m_normal.cross(tangent.normalized()), m_normal)
                : Frame(m_normal);
        its.shFrame = its.geoFrame;
    }

    AffineMap m_toWorld, m_toLocal;
    Vector3f m_normal;
    float m_area;
    bool m_flipNormals;
};

NORI_REGISTER_CLASS(Disk, "disk");

} // namespace
} // namespace nori
