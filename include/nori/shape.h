// Shapes (triangle meshes, analytic spheres) and the record of a ray hitting one.
// A shape is a set of primitives, so one acceleration structure serves every kind.
// This is geometry only: what lies on the surface (its BSDF, its area light, the media
// on either side, its normal or bump map) is attached by those objects themselves
// (NoriObject::attachTo) and used by the render layer (shading.h), which knows them.
#pragma once

#include <nori/bbox.h>
#include <nori/frame.h>
#include <nori/lightbounds.h>
#include <nori/object.h>
#include <nori/transform.h>

namespace nori {

class BSDF;
class Emitter;
class Medium;
class Shape;
class SurfaceShading;
class TMeshSet;
struct Intersection;

/// The media on the two sides of a surface, as a shape carries them: `interior` where
/// the geometric normal points away from, `exterior` where it points to. nullptr is
/// vacuum.
struct MediumInterface {
    const Medium *interior = nullptr;
    const Medium *exterior = nullptr;

    /// The medium on the side of the surface that direction d (world) points into.
    const Medium *toward(const Vector3f &d, const Vector3f &geometricNormal) const {
        return d.dot(geometricNormal) < 0.0f ? interior : exterior;
    }
};

/// A point sampled on a shape's surface.
struct ShapeSample {
    Point3f p;
    Point2f uv = Point2f(0.0f, 0.0f); ///< surface parameterisation at p (for textured lights)
    Normal3f n;                       ///< outward (geometric) normal at p
    float pdf = 0; ///< density: per area (sampleSurface) or per solid angle at the
                   ///< reference point (sampleFromReference)
    /// The primitive (a mesh's triangle) p lies on, or kUnknownPrimitive: a density query
    /// that knows it (a ray hit, a sample) needs not find it again from p.
    uint32_t primitive = kUnknownPrimitive;
    static constexpr uint32_t kUnknownPrimitive = UINT32_MAX;
};

/// What makes a surface partly absent: an alpha mask (a leaf's cut-out), α in [0, 1] at
/// each point. The render layer attaches one (shading.h: a shape's `alpha`, Mitsuba's
/// `mask`); the acceleration structure asks it before it accepts a hit, so every ray
/// (camera, scattered, shadow) passes through where the surface is absent and no
/// integrator needs to know.
class SurfaceOpacity {
public:
    virtual ~SurfaceOpacity() = default;
    /// α at a ray hit at p, given the shape's own uv there (Shape::hitPoint).
    virtual float opacityAtHit(const Point2f &shapeUV, const Point3f &p) const = 0;
    /// α at a point given by its texture uv (a light's sampled point, an emitter query).
    virtual float opacityAt(const Point2f &textureUV, const Point3f &p) const = 0;
};

/// Whether a point of opacity α is there: always for α ≥ 1, never for α ≤ 0, and otherwise
/// when a hash of the point's coordinates, uniform in [0, 1), falls below α (pbrt-v4's
/// AlphaMasked). The choice is fixed per point, so every ray and every light query sees the
/// same surface, and over the continuum of points a pixel covers it is present a fraction α
/// of the time, independently for every surface a ray crosses.
bool surfacePresent(float alpha, const Point3f &p);

struct Intersection {
    Point3f p;           ///< hit position
    Vector3f pError;     ///< bound on the absolute floating-point error of p
    float t = kInfinity; ///< ray parameter of the hit
    Point2f uv;          ///< surface parameterisation
    Frame shFrame;       ///< shading frame (interpolated normal)
    Frame geoFrame;      ///< geometric frame (true surface normal)
    Vector3f dpdu, dpdv; ///< position derivatives w.r.t. uv (for textures)
    /// Derivatives of the shading normal w.r.t. uv (zero for flat shading), for carrying
    /// ray differentials through curved mirrors and lenses.
    Vector3f dndu = Vector3f::Zero(), dndv = Vector3f::Zero();
    /// The footprint of a pixel at the hit (see raydifferential.h): position and uv
    /// change per pixel step in x and y; all zero for rays without differentials.
    Vector3f dpdx = Vector3f::Zero(), dpdy = Vector3f::Zero();
    float dudx = 0.0f, dudy = 0.0f, dvdx = 0.0f, dvdy = 0.0f;
    uint32_t primIndex = 0; ///< index of the primitive within the shape
    const Shape *shape = nullptr;
    /// The same shape, by Nori 2's name (its.mesh->getBSDF()); any shape, not only meshes.
    const Shape *mesh = nullptr;

    Vector3f toLocal(const Vector3f &d) const { return shFrame.toLocal(d); }
    Vector3f toWorld(const Vector3f &d) const { return shFrame.toWorld(d); }

    /// A ray leaving the surface in direction d, its origin pushed off the surface along
    /// the geometric normal (to the side d points to) by the error bound pError, so it
    /// cannot hit the surface again (PBR 4th ed. §6.8.6).
    Ray3f spawnRay(const Vector3f &d) const;
    /// A shadow-ray segment from the surface to `target`, ending just short of it.
    Ray3f spawnRayTo(const Point3f &target) const;
    /// Whether the world direction d lies on the same side of the geometric and of the
    /// shading surface. Integrators drop directions where the two disagree, so that a
    /// bent shading normal (normal map, vertex normals) cannot let light through the
    /// surface (Veach 1997, §5.3; pbrt-v3 §9.1).
    bool sidesAgree(const Vector3f &d) const { return geoFrame.n.dot(d) * shFrame.n.dot(d) > 0.0f; }
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

    /// The position and the shape's own uv of a hit, as setHitInformation sets its.p and
    /// its.uv (t set before): all an alpha mask needs to decide whether a candidate hit is
    /// there, so the default, which fills a whole Intersection, is worth overriding.
    virtual void hitPoint(uint32_t index, const Ray3f &ray, float t, const Point2f &hitCoords,
                          Point3f &p, Point2f &uv) const;

    /// setHitInformation for a hit found inside an instance (ray and hitCoords in the
    /// shape's space), carried to world space by toWorld (toLocal is its inverse).
    /// Points and tangents map by toWorld, normals by toLocal's transpose (the inverse
    /// transpose of toWorld), so they stay perpendicular under non-uniform scale.
    virtual void setInstancedHitInformation(uint32_t index, const Ray3f &ray,
                                            const Point2f &hitCoords, const AffineMap &toWorld,
                                            const AffineMap &toLocal, Intersection &its) const;

    /// Total surface area.
    virtual float getArea() const = 0;
    /// A cone that holds the normals sampleSurface() returns (the side an area light
    /// emits from), for the light tree's bounds. The default is the whole sphere, right
    /// for any shape; a mesh gives the cone of its faces.
    virtual DirectionCone normalBounds() const { return DirectionCone::entireSphere(); }
    /// Whether ref lies behind every point of the surface, as sampleSurface() orients its
    /// normals (n·(ref − p) ≤ 0 everywhere), so that a one-sided light on it sends ref
    /// nothing: a test an area light makes before sampling. False when unsure, as here.
    virtual bool facesAwayFrom(const Point3f &ref) const {
        (void)ref;
        return false;
    }

    /// A point uniformly distributed over the surface (pdf = 1/area).
    virtual ShapeSample sampleSurface(const Point2f &sample) const = 0;
    /// A point on the surface as seen from `ref`, with its pdf in solid angle at ref.
    /// `refNormal` is the shading normal at ref, or zero (a point in a medium): a shape may
    /// draw more directions where its cos θ is large. The default converts area sampling
    /// (pdf_ω = pdf_A · d²/|cos θ|); shapes that can do better (a sphere's visible cone, a
    /// small mesh's spherical triangles) override it together with pdfFromReference.
    virtual ShapeSample sampleFromReference(const Point3f &ref, const Normal3f &refNormal,
                                            const Point2f &sample) const;
    /// The solid-angle density at ref of sampleFromReference producing `point` (its p, n
    /// and primitive; its pdf is not read).
    virtual float pdfFromReference(const Point3f &ref, const Normal3f &refNormal,
                                   const ShapeSample &point) const;
    /// sampleSurface's point with its density in solid angle at ref: pdf_A · d²/|cos θ|.
    /// The default of the two above; an area light asks for it with `sampling="area"`.
    ShapeSample areaSampleFromReference(const Point3f &ref, const Point2f &sample) const;
    float areaPdfFromReference(const Point3f &ref, const Point3f &p, const Normal3f &n) const;

    /// Whether the shape renders itself (`visible`, default true): an invisible shape is
    /// a template that only its tmesh copies place.
    bool isVisible() const { return m_visible; }
    void setVisible(bool visible) { m_visible = visible; }
    /// The shape's <mesh type="tmesh"> copies, or nullptr without any.
    const std::shared_ptr<TMeshSet> &tmeshes() const { return m_tmeshes; }

    const BoundingBox3f &getBoundingBox() const { return m_bbox; }
    const BSDF *getBSDF() const { return m_bsdf.get(); }
    std::shared_ptr<BSDF> getBSDFPtr() const { return m_bsdf; }
    /// The uv scale and normal or bump map of the surface (shading.h), or nullptr.
    const SurfaceShading *getSurfaceShading() const { return m_shading.get(); }
    std::shared_ptr<const SurfaceShading> getSurfaceShadingPtr() const { return m_shading; }
    /// The alpha mask that makes parts of the surface absent, or nullptr (opaque).
    const SurfaceOpacity *getOpacity() const { return m_opacity.get(); }
    void setOpacity(std::shared_ptr<const SurfaceOpacity> opacity);
    /// Whether the hit of primitive `index` at distance t (hitCoords from rayIntersect) is
    /// on a present part of the surface (surfacePresent at the hit point).
    bool presentAt(uint32_t index, const Ray3f &ray, float t, const Point2f &hitCoords) const;
    /// The media inside and outside the surface (nullptr: vacuum).
    MediumInterface getMediumInterface() const { return {m_interior.get(), m_exterior.get()}; }
    /// Whether the shape bounds a medium (an `interior` or `exterior` child): rays crossing
    /// it change medium; a shape without one leaves a ray in the medium it was in.
    bool hasMediumInterface() const { return m_interior || m_exterior; }
    /// Whether the surface encloses a volume (every edge shared by an even number of
    /// triangles), which a medium inside it needs.
    virtual bool isClosed() const { return true; }
    /// The area light on this shape, or nullptr.
    const Emitter *getEmitter() const { return m_emitter.get(); }
    Emitter *getEmitter() { return m_emitter.get(); }
    /// Whether the shape is an area light (Nori 2).
    bool isEmitter() const { return m_emitter != nullptr; }
    std::shared_ptr<Emitter> getEmitterPtr() const { return m_emitter; }

    /// The slots that the objects on the surface fill when they attach themselves
    /// (BSDF::attachTo and the like); each throws when its slot is already taken.
    void setBSDF(std::shared_ptr<BSDF> bsdf);
    void setEmitter(std::shared_ptr<Emitter> emitter);
    /// `side` is "interior" or "exterior".
    void setMedium(const std::string &side, std::shared_ptr<Medium> medium);
    void setSurfaceShading(std::shared_ptr<const SurfaceShading> shading);

    /// Accepts any number of <mesh type="tmesh"> copies, and every child that attaches
    /// itself to a shape: one <bsdf>, one <emitter> (an area light on the shape), a
    /// <medium> named "interior" and one named "exterior".
    using NoriObject::addChild;
    void addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) override;
    /// Gives a shape without a BSDF the default diffuse one (Nori's behaviour), or the
    /// `null` one when it bounds a medium; warns when a medium boundary is not closed;
    /// builds the tmesh copies' shared Accel. Area lights and media on copied shapes are
    /// refused.
    void activate() override;

    EClassType getClassType() const override { return kClassType; }

protected:
    BoundingBox3f m_bbox;
    std::shared_ptr<const SurfaceShading> m_shading;
    std::shared_ptr<BSDF> m_bsdf;
    std::shared_ptr<Emitter> m_emitter;
    std::shared_ptr<Medium> m_interior, m_exterior;
    std::shared_ptr<const SurfaceOpacity> m_opacity;
    bool m_visible = true;
    std::shared_ptr<TMeshSet> m_tmeshes;
};

} // namespace nori
