// Integrators estimate the radiance arriving along a camera ray.
#pragma once

#include <nori/aov.h>
#include <nori/color.h>
#include <nori/object.h>
#include <nori/ray.h>
#include <nori/statestream.h>

namespace nori {

class Scene;
class Sampler;

/// Light a sample puts on the film at a position of its own choosing (light tracing: a
/// path from a light connected to the camera lands on any pixel). The film reconstructs a
/// pixel j from the splats of every sample of the render as (1/spp)·Σ value·f(position −
/// c_j)/F_j, where f is the reconstruction filter, c_j the pixel's centre and F_j = ∫ f(x −
/// c_j) dx over the image (1 away from the edges), so that a splat of `value` ≡ radiance ×
/// CameraConnection::importance × (the rest of the path's weight) is unbiased for the
/// filtered image whatever the filter (see SplatBuffer).
struct Splat {
    Point2f position; ///< film position in pixels, from the top-left corner
    Color3f value;
    /// 0: the image; k ≥ 1: the integrator's k-th extra layer (Integrator::splatLayers),
    /// reconstructed the same way, a debug view such as BDPT's strategies.
    int layer = 0;
    /// Lands at the sample's own film position (`position` is not used), with the camera
    /// ray's weight applied: a layer's share of the sample's own light.
    bool atSample = false;
};

/// What an integrator's image estimates. `nori --test-plugin` compares an integrator with
/// the built-in one of the same quantity (src/testing/integratortest.h): a course's
/// ambient-occlusion integrator with `ao`, not with a path tracer.
enum class IntegratorQuantity {
    Radiance,           ///< the radiance arriving at the camera (path_mis)
    AmbientOcclusion,   ///< unoccluded cosine-weighted fraction of the hemisphere (ao)
    AverageVisibility,  ///< unoccluded fraction within a distance (av)
    DirectIllumination, ///< emitted light plus light reflected once (direct)
    Whitted,            ///< direct light, continued through mirrors and glass (whitted)
    PointLight,         ///< one point light of the integrator's own (simple)
    Normals,            ///< the shading normal as a colour (normals)
    Material            ///< the BSDF's colour at the first hit (material)
};

/// The quantity of the course assignment whose integrator is registered as `name`: ao,
/// av, simple, direct (and direct_ems, direct_mats, direct_mis), whitted, normals,
/// material; Radiance for every other name.
IntegratorQuantity courseIntegratorQuantity(const std::string &name);
/// The built-in integrator that estimates `quantity` ("path_mis" for Radiance).
const char *referenceIntegrator(IntegratorQuantity quantity);

class Integrator : public NoriObject {
public:
    static constexpr EClassType kClassType = EIntegrator;

    /// Called once before rendering, after the scene is activated.
    virtual void preprocess(const Scene *scene) { (void)scene; }
    /// The radiance arriving at ray.o from direction -ray.d.
    virtual Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const = 0;

    /// Whether the integrator puts light on pixels other than the one a camera ray samples
    /// (light tracing): the render loop then calls LiAndSplats instead of Li.
    virtual bool splats() const { return false; }
    /// Li, and the splats of the same sample appended to `splats`. An integrator that
    /// splats estimates a pixel from both: Li from the camera ray (light seen directly, for
    /// a light tracer) and the splats (every other path).
    virtual Color3f LiAndSplats(const Scene *scene, Sampler *sampler, const Ray3f &ray,
                                std::vector<Splat> &splats) const {
        (void)splats;
        return Li(scene, sampler, ray);
    }

    /// The names of the extra EXR layers (channels R, G, B) that an integrator that splats
    /// fills with splats of layer 1, 2, ... (Splat::layer); none by default.
    virtual std::vector<std::string> splatLayers() const { return {}; }
    /// Whether the integrator renders what the camera sees only through delta BSDFs
    /// (mirrors, smooth glass, and what is seen in them). A light tracer cannot: such
    /// paths have no vertex it can connect to the lens. `nori --test-plugin` leaves out
    /// its scenes with such surfaces in view for an integrator that says false.
    virtual bool rendersSpecularInView() const { return true; }

    /// Integrators that work in passes (the progressive photon mapper traces a photon map
    /// per pass): the render loop calls beginPass before rendering sample indices
    /// [firstSample, endSample) of every pixel and endPass once that pass is complete (not
    /// for a pass a cancel drops). During a pass, Li may update state of the pixel it is
    /// called for (Sampler::pixel()): a pixel is rendered by one thread at a time.
    virtual void beginPass(const Scene *scene, uint32_t firstSample, uint32_t endSample) {
        (void)scene, (void)firstSample, (void)endSample;
    }
    virtual void endPass(const Scene *scene) { (void)scene; }
    /// The state that passes leave in the integrator (the progressive photon mapper's
    /// radii and fluxes), for a checkpoint of the render (checkpoint.h): written after a
    /// pass, read back before the next one instead of the passes that made it. Nothing
    /// for integrators whose passes leave no state.
    virtual void saveState(StateWriter &state) const { (void)state; }
    virtual void loadState(StateReader &state) { (void)state; }
    /// The most samples per pixel a pass of the render loop may take (0: no limit).
    virtual size_t maxSamplesPerPass() const { return 0; }
    /// Whether Li accounts for participating media (<medium> in a scene): `nori
    /// --test-plugin` then also compares the integrator with volpath on a scene with a
    /// homogeneous and a heterogeneous medium. Integrators that ignore media keep false.
    virtual bool handlesMedia() const { return false; }
    /// What the integrator did besides tracing camera paths, for `nori` to print after
    /// the render ("photon map: ..."); empty for most.
    virtual std::string renderSummary() const { return {}; }
    /// What the image estimates (see IntegratorQuantity). By default the quantity of the
    /// course assignment the plugin is named after (courseIntegratorQuantity), so a
    /// course's `ao.cpp` needs nothing; an integrator of such a quantity under another
    /// name overrides this.
    virtual IntegratorQuantity quantity() const { return courseIntegratorQuantity(pluginName()); }

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
