/*
 * bdpt — bidirectional path tracing (Veach 1997, ch. 10; PBR 3rd ed. §16.3): each sample
 * traces a subpath from the camera and one from a light (picked by power) and joins them
 * in every way (s, t), s vertices from the light and t from the camera: s = 0 is the
 * camera subpath finding a light, s = 1 next-event estimation, t = 1 light tracing (a
 * splat on whichever pixel sees the point), the rest a segment between two surfaces.
 * Multiple importance sampling weighs the strategies, so each path is found by the one
 * that samples it best: caustics seen on diffuse surfaces (light, glass, floor, camera)
 * by light tracing, light seen in mirrors by the camera subpath. The weights follow
 * Veach's recursive form (§10.2.1): no strategy's density is rebuilt from scratch. See
 * include/nori/bdpt.h and docs/bdpt.md. Cameras: perspective and thinlens; scenes with
 * participating media are an error.
 *
 * Parameters:
 *   maxDepth    integer  -1       scattering events of a whole path (-1: unbounded), as the
 *                                 path tracers count them
 *   rrDepth     integer  3        Russian roulette from this event of either subpath on
 *   heuristic   string   "power"  MIS heuristic: "power" (exponent 2) or "balance"
 *   strategies  boolean  false    also write each strategy's image, weighted and not, as
 *                                 EXR layers s<s>t<t> and s<s>t<t>.unweighted (Veach's
 *                                 figure 10.3); up to maxDepth 5, all paths if unbounded
 *
 *   <integrator type="bdpt"/>
 *
 *   <integrator type="bdpt">
 *       <integer name="maxDepth" value="5"/> <string name="heuristic" value="balance"/>
 *   </integrator>
 */
#include <nori/bdpt.h>
#include <nori/emitter.h>
#include <nori/sampler.h>
#include <nori/scene.h>

namespace nori {
namespace {

MISHeuristic readHeuristic(const PropertyList &props) {
    const std::string name = props.getString("heuristic", "power");
    if (name == "power")
        return MISHeuristic::Power;
    if (name == "balance")
        return MISHeuristic::Balance;
    throw NoriException("bdpt: 'heuristic' is \"{}\"; it must be \"power\" or \"balance\"", name);
}

class BDPTIntegrator : public Integrator {
public:
    explicit BDPTIntegrator(const PropertyList &props)
        : m_paths(PathDepth::read(props, "bdpt"), readHeuristic(props)) {}

    void preprocess(const Scene *scene) override { BidirectionalPaths::validate(*scene, "bdpt"); }

    bool splats() const override { return true; }

    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const override {
        std::vector<Splat> splats;
        return m_paths.estimate(*scene, *sampler, ray, splats);
    }

    Color3f LiAndSplats(const Scene *scene, Sampler *sampler, const Ray3f &ray,
                        std::vector<Splat> &splats) const override {
        return m_paths.estimate(*scene, *sampler, ray, splats);
    }

    std::string toString() const override {
        return fmt::format("BDPT[maxDepth={}, rrDepth={}, heuristic={}]", m_paths.depth().maxDepth,
                           m_paths.depth().rrDepth,
                           m_paths.heuristic() == MISHeuristic::Power ? "power" : "balance");
    }

private:
    BidirectionalPaths m_paths;
};

NORI_REGISTER_CLASS(BDPTIntegrator, "bdpt");

} // namespace
} // namespace nori
