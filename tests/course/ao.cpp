// Ambient occlusion as a Nori 2 course's assignment has students write it: one
// cosine-weighted direction about the shading normal, whose visibility is the estimate
// (cos θ / π over the density cos θ / π), under the name the handout gives it. Test
// data of tests/CMakeLists.txt ("course"): it replaces our `ao`. Compiled with
// -DCOURSE_PLANTED_BUG it draws uniform directions and forgets their weight 2 cos θ.
#include <nori/integrator.h>
#include <nori/sampler.h>
#include <nori/scene.h>
#include <nori/warp.h>

NORI_NAMESPACE_BEGIN

class AOIntegrator : public Integrator {
public:
    AOIntegrator(const PropertyList &props) {}

    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const {
        Intersection its;
        if (!scene->rayIntersect(ray, its))
            return Color3f(0.0f);
#ifdef COURSE_PLANTED_BUG
        Vector3f local = Warp::squareToUniformHemisphere(sampler->next2D());
#else
        Vector3f local = Warp::squareToCosineHemisphere(sampler->next2D());
#endif
        Ray3f shadowRay(its.p, its.shFrame.toWorld(local));
        return scene->rayIntersect(shadowRay) ? Color3f(0.0f) : Color3f(1.0f);
    }

    std::string toString() const {
        return "AOIntegrator[]";
    }
};

NORI_REGISTER_CLASS(AOIntegrator, "ao");
NORI_NAMESPACE_END
