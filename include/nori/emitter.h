// Light sources. Directions are in world space; `wi` points from the reference point
// toward the light.
#pragma once

#include <nori/bbox.h>
#include <nori/color.h>
#include <nori/lightbounds.h>
#include <nori/object.h>
#include <nori/ray.h>
#include <nori/shape.h>
#include <nori/texture.h>

#include <optional>

namespace nori {

class Shape;

/// An emitter query. It is also the TextureQuery of the emitter's point (p, uv and the
/// footprint), so a textured radiance is looked up with the record itself.
struct EmitterQueryRecord : TextureQuery {
    Point3f ref; ///< the point being lit
    /// The shading normal at ref, by which a light may draw more directions where cos θ
    /// is large (a small triangle mesh does); zero: none (a point in a medium, or a
    /// caller that does not say). Sampling and density queries must agree on it.
    Normal3f refNormal = Normal3f::Zero();
    Normal3f n;       ///< surface normal at p (area lights)
    Vector3f wi;      ///< unit direction from ref toward p
    float pdf = 0.0f; ///< solid-angle density of wi at ref (for delta lights: 1)
    /// From ref to p, for the visibility test of course code (see setShadowRay); our
    /// integrators use Intersection::spawnRayTo, which is robust at every scale.
    Ray3f shadowRay;
    /// The primitive of the light's shape that p lies on (ShapeSample::primitive): set by
    /// a ray hit and by sample(); unknown for a record built from a point.
    uint32_t primitive = ShapeSample::kUnknownPrimitive;
    /// For a camera ray that escapes to an environment: how its direction changes per
    /// pixel in x and y (from the ray differentials), for a filtered lookup. Zero
    /// otherwise: the lookup then matches the sampling density exactly.
    Vector3f dwdx = Vector3f::Zero(), dwdy = Vector3f::Zero();
    // Inherited from TextureQuery: p, the sampled (or queried) point on the emitter, and
    // its uv and footprint.

    EmitterQueryRecord() = default;

    /// Sets shadowRay toward a point `distance` along wi: from Nori 2's Epsilon (kEpsilon)
    /// past ref, so that it does not find the surface ref lies on (courses test
    /// scene->rayIntersect(lRec.shadowRay)), to just before p.
    void setShadowRay(float distance) {
        shadowRay = Ray3f(ref, wi, kEpsilon, distance * (1.0f - kShadowEpsilon));
    }
    explicit EmitterQueryRecord(const Point3f &ref) : ref(ref) {}
    EmitterQueryRecord(const Point3f &ref, const Point3f &p, const Normal3f &n)
        : ref(ref), n(n), wi((p - ref).normalized()) {
        this->p = p;
    }
    /// The light leaving a ray hit toward ref: p, n (geometric), uv and footprint.
    EmitterQueryRecord(const Point3f &ref, const Intersection &its)
        : TextureQuery(its), ref(ref), n(its.geoFrame.n), wi((its.p - ref).normalized()),
          primitive(its.primIndex) {}
    /// The light an escaping ray sees of an infinite emitter (environment).
    explicit EmitterQueryRecord(const Ray3f &ray, bool filtered = false)
        : ref(ray.o), wi(ray.d.normalized()) {
        if (filtered && ray.hasDifferentials) {
            dwdx = ray.rxDirection.normalized() - wi;
            dwdy = ray.ryDirection.normalized() - wi;
        }
    }
};

/// The scene's bounding sphere, which lights at infinity (directional, environment) need:
/// their power is what crosses its disk, and their shadow rays must leave it.
struct SceneBoundingSphere {
    Point3f center = Point3f(0.0f, 0.0f, 0.0f);
    float radius = 1.0f; ///< until a scene sets it

    /// The sphere around `bounds` (kept as it is for an empty scene).
    void set(const BoundingBox3f &bounds);
    /// π r², the cross-section that light from one direction crosses.
    float diskArea() const { return kPi * radius * radius; }
    /// Sets lRec.p to a point beyond the sphere from lRec.ref along lRec.wi, with the normal
    /// facing back and the shadow ray to it.
    void placeBeyond(EmitterQueryRecord &lRec) const;
    /// A photon ray of light arriving from the direction `toLight`: its origin is a point
    /// of the disk of the sphere facing toLight (uniform by `sample`), one radius out,
    /// so that it crosses the whole scene; the direction is −toLight. Sets the ray, the
    /// point and the position density of `emission` and returns the disk's area, the
    /// photon's weight per unit of radiance over direction density.
    float photonRayFrom(const Vector3f &toLight, const Point2f &sample,
                        struct EmissionSample &emission) const;
};

/// The densities of a photon ray's origin and direction (Emitter::sampleEmission), with
/// which bidirectional path tracing weighs its strategies (Veach 1997, §10.2).
struct EmissionDensity {
    /// Area density of the origin: per unit area of the light's surface, or of the disk of
    /// the scene's bounding sphere for lights at infinity; 1 for a point (a delta).
    float position = 0.0f;
    /// Solid-angle density of the direction; 1 for a directional light (a delta).
    float direction = 0.0f;
};

/// A photon ray leaving a light (Emitter::sampleEmission).
struct EmissionSample {
    Ray3f ray;  ///< the photon's ray (its origin moved past the surface's rounding)
    Point3f p;  ///< the point it leaves from: on the light, or on the disk at infinity
    Normal3f n; ///< the light's surface normal at p (area lights), else zero
    EmissionDensity density;
    EmissionSample() : p(0.0f, 0.0f, 0.0f), n(0.0f, 0.0f, 0.0f) {}
};

class Emitter : public NoriObject {
public:
    static constexpr EClassType kClassType = EEmitter;

    /// Samples a point on the light as seen from lRec.ref; fills p, n, wi, pdf and
    /// shadowRay and returns radiance / pdf (zero when sampling fails).
    virtual Color3f sample(EmitterQueryRecord &lRec, const Point2f &sample) const = 0;
    /// Radiance leaving p toward ref (lRec.p, n and wi set).
    virtual Color3f eval(const EmitterQueryRecord &lRec) const = 0;
    /// Solid-angle density at ref of sampling lRec.wi (p and n set when the emitter has a
    /// shape, so the χ² test can query directions).
    virtual float pdf(const EmitterQueryRecord &lRec) const = 0;
    /// Lights with a delta distribution (point, spot, distant) cannot be hit by rays.
    virtual bool isDelta() const { return false; }
    /// Lights at infinity (environment maps) are seen by rays that leave the scene:
    /// eval() then takes a record made from the escaping ray.
    virtual bool isInfinite() const { return false; }
    /// Whether the light must be nested in a shape (area lights); the scene rejects such
    /// a light at the top level.
    virtual bool requiresShape() const { return false; }
    /// Total emitted power (flux); the scene picks lights in proportion to its luminance.
    virtual Color3f getPower() const = 0;
    /// Where the light is, which way it faces and its power, for choosing among many
    /// lights by importance at a point (LightBVH). None (the default) for lights at
    /// infinity and for plugins that give none: those are chosen beside the light tree.
    virtual std::optional<LightBounds> lightBounds() const { return std::nullopt; }

    /// Samples a photon leaving the light (photon mapping, light tracing, BDPT): fills
    /// `emission` (the ray, the point and normal it leaves from, the densities of both) and
    /// returns its power weight Le·|cos θ|/(pdf_A·pdf_ω) (for a delta light I(ω)/pdf_ω),
    /// whose mean over the samples is getPower(). `positionSample` picks the point (on the
    /// surface, or on the disk a light at infinity crosses the scene's bounding sphere
    /// through), `directionSample` the direction. Every light of the project emits
    /// photons; a plugin that does not override this cannot be used by the photon mappers,
    /// the light tracer or bdpt, which then stop with an error naming it.
    virtual Color3f sampleEmission(EmissionSample &emission, const Point2f &positionSample,
                                   const Point2f &directionSample) const;
    /// sampleEmission's ray and weight alone.
    Color3f samplePhoton(Ray3f &ray, const Point2f &positionSample,
                         const Point2f &directionSample) const;
    /// The densities with which sampleEmission() emits from the point p (normal n, zero
    /// for lights without a surface) along the unit `direction` (away from the light):
    /// what bdpt's MIS weights need of a light vertex that it did not sample this way. For
    /// lights at infinity p is not used. A plugin that overrides sampleEmission overrides
    /// this too.
    virtual EmissionDensity emissionDensity(const Point3f &p, const Normal3f &n,
                                            const Vector3f &direction) const;
    /// Whether the light lies at infinity: environments (isInfinite) and directional
    /// lights, whose photons start on the disk of the scene's bounding sphere. Light
    /// leaving them has the same density at any distance (bdpt's MIS weights).
    virtual bool liesAtInfinity() const { return isInfinite(); }

    /// Tells the light the bounds of the scene it lights, before getPower() is asked:
    /// lights at infinity (directional, environment) need the scene's bounding sphere.
    virtual void setSceneBounds(const BoundingBox3f &bounds) { (void)bounds; }

    /// The shape an area light is attached to, or nullptr.
    const Shape *getShape() const { return m_shape; }
    void setShape(const Shape *shape) { m_shape = shape; }

    /// The textures behind the emitter's colour and float parameters.
    const TextureParameters &textures() const { return m_textures; }

    /// Becomes the area light of a shape it is nested in.
    bool attachTo(NoriObject &parent, const std::string &name) override;

    EClassType getClassType() const override { return kClassType; }

protected:
    /// emissionDensity() of a light at infinity whose photons cross the disk of `sphere`
    /// and whose directions pdf() gives (for lRec.wi toward the light).
    EmissionDensity densityAtInfinity(const SceneBoundingSphere &sphere,
                                      const Vector3f &direction) const;
    /// Reads a delta light's `intensity` (W/sr) or `power` (W), exactly one of them, and
    /// returns the intensity: power / solidAngle, where solidAngle = ∫ of the light's
    /// angular profile over the sphere (4π for a point light).
    static Color3f readIntensity(const PropertyList &props, const std::string &plugin,
                                 float solidAngle);
    /// Fills lRec for a light at the point `position` (p, wi, n, the delta "pdf" 1 and the
    /// shadow ray) and returns the squared distance to it, or 0 when ref is on it.
    static float aimAtPoint(EmitterQueryRecord &lRec, const Point3f &position);

    const Shape *m_shape = nullptr;
    /// Read every colour and float parameter through this (see BSDF::m_textures).
    TextureParameters m_textures;
};

} // namespace nori
