/*
 * planted_ao_cosine — a negative control: a student's ambient occlusion that samples the
 * hemisphere uniformly and averages the visibility, forgetting the weight cos θ/(π p) =
 * 2 cos θ of each direction. Unoccluded points are still 1; where the horizon is
 * partly blocked (a sphere's contact with the floor) it is wrong, and the integrator
 * test, against the built-in `ao`, must say so.
 *
 * No parameters.
 *
 *   <integrator type="planted_ao_cosine"/>
 */
#include <nori/integrator.h>
#include <nori/sampler.h>
#include <nori/scene.h>
#include <nori/warp.h>

namespace nori {

class PlantedAoCosine : public Integrator {
public:
    explicit PlantedAoCosine(const PropertyList &) {}

    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const override {
        Intersection its;
        if (!scene->rayIntersect(ray, its))
            return Color3f(0.0f);
        Frame frame = its.shFrame;
        if (frame.n.dot(ray.d) > 0.0f)
            frame = Frame(-frame.s, frame.t, -frame.n);
        const Vector3f direction =
            frame.toWorld(Warp::squareToUniformHemisphere(sampler->next2D()));
        // The bug: visibility alone, without 2 cos θ.
        return Color3f(scene->rayIntersect(its.spawnRay(direction)) ? 0.0f : 1.0f);
    }

    /// Not named after the course's "ao", so it says what it estimates.
    IntegratorQuantity quantity() const override { return IntegratorQuantity::AmbientOcclusion; }

    std::string toString() const override { return "PlantedAoCosine[]"; }
};

NORI_REGISTER_CLASS(PlantedAoCosine, "planted_ao_cosine");

} // namespace nori
