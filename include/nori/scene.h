// The root object of a render: shapes, integrator, camera and sampler.
#pragma once

#include <nori/camera.h>
#include <nori/dpdf.h>
#include <nori/emitter.h>
#include <nori/instance.h>
#include <nori/integrator.h>
#include <nori/lightbvh.h>
#include <nori/sampler.h>

#include <unordered_map>

namespace nori {

class Scene : public NoriObject {
public:
    static constexpr EClassType kClassType = EScene;

    explicit Scene(const PropertyList &props);
    ~Scene() override;

    const Integrator *getIntegrator() const { return m_integrator.get(); }
    Integrator *getIntegrator() { return m_integrator.get(); }
    const Camera *getCamera() const { return m_camera.get(); }
    const Sampler *getSampler() const { return m_sampler.get(); }
    Sampler *getSampler() { return m_sampler.get(); }
    /// Whether the scene named no sampler and got the default, `sobol` (Nori 2's default
    /// is `independent`, which Nori 2's test files then keep: see the ttest plugin).
    bool hasDefaultSampler() const { return m_defaultSampler; }
    /// Every shape in the scene itself (not those in shape groups), with invisible ones.
    const std::vector<std::shared_ptr<Shape>> &getShapes() const { return m_contents.shapes(); }
    const BoundingBox3f &getBoundingBox() const { return m_contents.accel().getBoundingBox(); }
    /// The triangle meshes among getShapes() (Nori 2's list; spheres and instances are
    /// not meshes, so course code that looks for lights should use getEmitters()).
    const std::vector<Mesh *> &getMeshes() const { return m_meshes; }
    /// The acceleration structure over shapes and instances (a pointer, as in Nori 2).
    const Accel *getAccel() const { return &m_contents.accel(); }
    /// Every light: area lights of shapes and the scene's own (point) lights.
    const std::vector<std::shared_ptr<Emitter>> &getEmitters() const { return m_emitters; }

    /// Picks a light with probability proportional to its power (luminance), wherever
    /// it is to light (photon emission); `u` is rescaled for reuse. nullptr when the
    /// scene has no light.
    const Emitter *sampleEmitter(float &u, float &pmf) const;
    /// The probability that sampleEmitter(u, pmf) picks `emitter`.
    float emitterPmf(const Emitter *emitter) const;
    /// Picks a light to light the point p (n: the surface normal there, zero in a
    /// medium) for next-event estimation, as the scene's `lightSampler` says: by its
    /// importance at p (`bvh`, the light tree; the default) or by power alone (`power`).
    /// nullptr when no light can reach p.
    const Emitter *sampleEmitter(const Point3f &p, const Normal3f &n, float &u, float &pmf) const;
    /// The probability that sampleEmitter(p, n, u, pmf) picks `emitter`.
    float emitterPmf(const Point3f &p, const Normal3f &n, const Emitter *emitter) const;
    /// The lights at infinity, which rays that leave the scene see.
    const std::vector<const Emitter *> &getInfiniteEmitters() const { return m_infiniteEmitters; }

    /// The camera ray for a film sample (Camera::sampleRay), with ray differentials when
    /// some texture of the scene is filtered over the pixel footprint (they cost about 10%
    /// of the render time, for nothing in a scene without such textures).
    Color3f sampleCameraRay(Ray3f &ray, const Point2f &samplePosition,
                            const Point2f &apertureSample) const;

    /// Closest intersection along the ray's segment, completed by its shape
    /// (completeHit in shading.h: uvScale, texture footprint, normal or bump map).
    bool rayIntersect(const Ray3f &ray, Intersection &its) const;
    /// Whether anything blocks the ray's segment (a shadow ray).
    bool rayIntersect(const Ray3f &ray) const;

    /// Rays traced through rayIntersect so far, over all threads.
    uint64_t rayCount() const;
    /// "3 shapes (1,024 triangles), 2 emitters; BVH of 1,026 primitives built in 4 ms",
    /// and the instances when there are any: what nori prints before rendering (Nori and
    /// pbrt print the same).
    std::string statisticsSummary() const;

    using NoriObject::addChild;

    void addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) override;
    /// Builds the acceleration structure, adds a default sampler, checks completeness.
    void activate() override;
    std::string toString() const override;

    EClassType getClassType() const override { return kClassType; }

private:
    ShapeCollection m_contents;
    std::vector<Mesh *> m_meshes;
    std::vector<std::shared_ptr<Emitter>> m_emitters;
    std::vector<const Emitter *> m_infiniteEmitters;
    DiscretePDF m_emitterPdf;
    LightBVH m_lightTree;
    bool m_lightsByPower = false; ///< `lightSampler` is "power": no tree
    std::unordered_map<const Emitter *, size_t> m_emitterIndex;
    std::shared_ptr<Integrator> m_integrator;
    std::shared_ptr<Camera> m_camera;
    std::shared_ptr<Sampler> m_sampler;
    double m_buildSeconds = 0.0;
    bool m_needsRayDifferentials = false;
    bool m_defaultSampler = false;
    struct RayCounter; ///< a count per thread (TBB), summed when asked
    std::unique_ptr<RayCounter> m_rayCounter;
};

} // namespace nori
