// A Whitted-style integrator as a Nori 2 course's assignment has students write it:
// emitted light, one light sample at diffuse surfaces (a light chosen uniformly), and
// mirrors and glass followed with probability 0.95, under the name the handout gives it.
// Test data of tests/CMakeLists.txt ("course"): it replaces our `whitted`. Its
// constructor's unused parameter is a warning, not an error, in a user's file. Compiled
// with -DCOURSE_PLANTED_BUG it forgets to divide by the probability 0.95 of continuing.
#include <nori/bsdf.h>
#include <nori/emitter.h>
#include <nori/integrator.h>
#include <nori/sampler.h>
#include <nori/scene.h>

NORI_NAMESPACE_BEGIN

class WhittedIntegrator : public Integrator {
public:
    WhittedIntegrator(const PropertyList &props) { /* No parameters this time */
    }

    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const {
        Intersection its;
        if (!scene->rayIntersect(ray, its))
            return Color3f(0.0f);

        Color3f Le(0.0f);
        if (its.mesh->isEmitter())
            Le = its.mesh->getEmitter()->eval(EmitterQueryRecord(ray.o, its));

        const BSDF *bsdf = its.mesh->getBSDF();
        if (bsdf->isDiffuse()) {
            const std::vector<std::shared_ptr<Emitter>> &emitters = scene->getEmitters();
            if (emitters.empty())
                return Le;
            size_t count = emitters.size();
            size_t index = std::min(count - 1, size_t(sampler->next1D() * count));
            EmitterQueryRecord lRec(its.p);
            Color3f radiance = emitters[index]->sample(lRec, sampler->next2D());
            if (radiance.isZero() || scene->rayIntersect(lRec.shadowRay))
                return Le;
            BSDFQueryRecord bRec(its.toLocal(-ray.d), its.toLocal(lRec.wi), ESolidAngle);
            bRec.uv = its.uv;
            bRec.p = its.p;
            float cosTheta = std::abs(Frame::cosTheta(bRec.wo));
            return Le + bsdf->eval(bRec) * radiance * cosTheta * float(count);
        }

        if (sampler->next1D() > 0.95f)
            return Le;
        BSDFQueryRecord bRec(its.toLocal(-ray.d));
        bRec.uv = its.uv;
        bRec.p = its.p;
        Color3f weight = bsdf->sample(bRec, sampler->next2D());
        if (weight.isZero())
            return Le;
#ifdef COURSE_PLANTED_BUG
        float continuation = 1.0f;
#else
        float continuation = 0.95f;
#endif
        return Le + weight * Li(scene, sampler, Ray3f(its.p, its.toWorld(bRec.wo))) / continuation;
    }

    std::string toString() const {
        return "WhittedIntegrator[]";
    }
};

NORI_REGISTER_CLASS(WhittedIntegrator, "whitted");
NORI_NAMESPACE_END
