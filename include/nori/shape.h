// Shapes (triangle meshes, analytic spheres) and the record of a ray hitting one.
// A shape is a set of primitives, so one acceleration structure serves every kind.
#pragma once

#include <nori/bbox.h>
#include <nori/frame.h>
#include <nori/object.h>

namespace nori {

class BSDF;
class Emitter;
class Shape;

/// A point sampled on a shape's surface.
struct ShapeSample {
    Point3f p;
    Normal3f n;    ///< outward (geometric) normal at p
    float pdf = 0; ///< density: per area (sampleSurface) or per solid angle at the
                   ///< reference point (sampleFromReference)
};

struct Intersection {
    Point3f p;           ///< hit position
    Vector3f pError;     ///< bound on the absolute floating-point error of p
    float t = kInfinity; ///< ray parameter of the hit
    Point2f uv;          ///< surface parameterisation
    Frame shFrame;       ///< shading frame (interpolated normal)
    Frame geoFrame;      ///< geometric frame (true surface normal)
    Vector3f dpdu, dpdv; ///< position derivatives w.r.t. uv (for textures)
    float dudx = 0.0f, dudy = 0.0f, dvdx = 0.0f, dvdy = 0.0f; ///< uv derivatives on screen
    uint32_t primIndex = 0; ///< index of the primitive within the shape
    const Shape *shape = nullptr;

    Vector3f toLocal(const Vector3f &d) const { return shFrame.toLocal(d); }
    Vector3f toWorld(const Vector3f &d) const { return shFrame.toWorld(d); }

    /// A ray leaving the surface in direction d, its origin pushed off the surface along
    /// the geometric normal (to the side d points to) by the error bound pError, so it
    /// cannot hit the surface again (PBR 4th ed. §6.8.6).
    Ray3f spawnRay(const Vector3f &d) const;
    /// A shadow-ray segment from the surface to `target`, ending just short of it.
    Ray3f spawnRayTo(const Point3f &target) const;
};

class Shape : public NoriObject {
public:
    static constexpr EClassType kClassType = EMesh;

    virtual uint32_t getPrimitiveCount() const = 0;
    virtual BoundingBox3f getPrimitiveBoundingBox(uint32_t index) const = 0;
    virtual Point3f getPrimitiveCentroid(uint32_t index) const = 0;
    /// Intersects one primitive with the ray's segment [mint, maxt]. On a hit, stores
    /// the distance and two shape-specific coordinates (e.g. barycentrics) for
    /// setHitInformation and returns true.
    virtual bool rayIntersect(uint32_t index, const Ray3f &ray, float &t,
                              Point2f &hitCoords) const = 0;
    /// Fills every field of `its` but t, which the caller has set.
    virtual void setHitInformation(uint32_t index, const Ray3f &ray, const Point2f &hitCoords,
                                   Intersection &its) const = 0;

    /// Total surface area.
    virtual float getArea() const = 0;
    /// A point uniformly distributed over the surface (pdf = 1/area).
    virtual ShapeSample sampleSurface(const Point2f &sample) const = 0;
    /// A point on the surface as seen from `ref`, with its pdf in solid angle at ref. The
    /// default converts area sampling (pdf_ω = pdf_A · d²/|cos θ|); shapes that can do
    /// better (a sphere's visible cone) override it together with pdfFromReference.
    virtual ShapeSample sampleFromReference(const Point3f &ref, const Point2f &sample) const;
    /// The solid-angle density at ref of sampleFromReference producing (p, n).
    virtual float pdfFromReference(const Point3f &ref, const Point3f &p, const Normal3f &n) const;

    const BoundingBox3f &getBoundingBox() const { return m_bbox; }
    const BSDF *getBSDF() const { return m_bsdf.get(); }
    std::shared_ptr<BSDF> getBSDFPtr() const { return m_bsdf; }
    /// The area light on this shape, or nullptr.
    const Emitter *getEmitter() const { return m_emitter.get(); }
    std::shared_ptr<Emitter> getEmitterPtr() const { return m_emitter; }

    /// Accepts one <bsdf> and one <emitter> (which becomes an area light on the shape).
    void addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) override;
    /// Gives a shape without a BSDF the default diffuse one (Nori's behaviour).
    void activate() override;

    EClassType getClassType() const override { return kClassType; }

protected:
    BoundingBox3f m_bbox;
    std::shared_ptr<BSDF> m_bsdf;
    std::shared_ptr<Emitter> m_emitter;
};

} // namespace nori
