// Integrators estimate the radiance arriving along a camera ray.
#pragma once

#include <nori/aov.h>
#include <nori/color.h>
#include <nori/object.h>
#include <nori/ray.h>

namespace nori {

class Scene;
class Sampler;

class Integrator : public NoriObject {
public:
    static constexpr EClassType kClassType = EIntegrator;

    /// Called once before rendering, after the scene is activated.
    virtual void preprocess(const Scene *scene) { (void)scene; }
    /// The radiance arriving at ray.o from direction -ray.d.
    virtual Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const = 0;

    /// The AOV layers the scene asks for: <string name="aovs" value="albedo,normal"/>,
    /// which every integrator accepts (the render loop computes them, see aov.h).
    const std::vector<AOV> &aovs() const { return m_aovs; }
    void readCommonProperties(const PropertyList &props) override {
        m_aovs = parseAOVList(props.getString("aovs", ""), "'aovs'");
    }

    EClassType getClassType() const override { return kClassType; }

private:
    std::vector<AOV> m_aovs;
};

} // namespace nori
