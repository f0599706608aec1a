/*
 * bdpt — bidirectional path tracing (Veach 1997, ch. 10; PBR 3rd ed. §16.3): each sample
 * traces a subpath from the camera and one from a light (picked by power) and joins them
 * in every way (s, t), s vertices from the light and t from the camera: s = 0 is the
 * camera subpath finding a light, s = 1 next-event estimation (its light picked as the
 * path tracers pick it: by the light tree's importance at the point, unless the scene's
 * lightSampler is "power"), t = 1 light tracing (a splat on whichever pixel sees the
 * point), the rest a segment between two surfaces.
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
 *                                 figure 10.3), for paths of up to 5 scattering events
 *                                 (maxDepth if smaller)
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

#include <map>

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
        : m_paths(PathDepth::read(props, "bdpt"), readHeuristic(props)) {
        if (props.getBoolean("strategies", false)) {
            // The debug view's layers: every strategy of paths of up to 5 events, by
            // length, then by s (Veach 1997, figure 10.3).
            const int longest = m_paths.depth().maxDepth < 0
                                    ? kLongestStrategyPath
                                    : std::min(m_paths.depth().maxDepth, kLongestStrategyPath);
            for (int events = 0; events <= longest; ++events)
                for (int s = 0; s <= events + 1; ++s) {
                    const int t = events + 2 - s;
                    if (!m_paths.allowed(s, t))
                        continue;
                    m_layerOf[{s, t}] = static_cast<int>(m_layerNames.size()) + 1;
                    m_layerNames.push_back(fmt::format("s{}t{}", s, t));
                    m_layerNames.push_back(fmt::format("s{}t{}.unweighted", s, t));
                }
        }
    }

    void preprocess(const Scene *scene) override { BidirectionalPaths::validate(*scene, "bdpt"); }

    bool splats() const override { return true; }
    std::vector<std::string> splatLayers() const override { return m_layerNames; }

    /// The strategies whose light lands on the camera ray's own pixel; those of t = 1 land
    /// anywhere, as splats (LiAndSplats, which the render loop calls).
    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const override {
        std::vector<Splat> splats;
        return m_paths.estimate(*scene, *sampler, ray, splats);
    }

    Color3f LiAndSplats(const Scene *scene, Sampler *sampler, const Ray3f &ray,
                        std::vector<Splat> &splats) const override {
        if (m_layerOf.empty())
            return m_paths.estimate(*scene, *sampler, ray, splats);
        // The debug view: each strategy's light, weighted and not, as splats of its layers.
        std::vector<Splat> layers;
        Color3f radiance =
            m_paths.estimate(*scene, *sampler, ray, splats, [&](const StrategySample &strategy) {
                const auto layer = m_layerOf.find({strategy.s, strategy.t});
                if (layer == m_layerOf.end() || (strategy.unweighted == 0.0f).all())
                    return;
                const Color3f weighted = strategy.unweighted * strategy.weight;
                layers.push_back({strategy.position, weighted, layer->second, !strategy.splat});
                layers.push_back(
                    {strategy.position, strategy.unweighted, layer->second + 1, !strategy.splat});
            });
        splats.insert(splats.end(), layers.begin(), layers.end());
        return radiance;
    }

    std::string toString() const override {
        return fmt::format("BDPT[maxDepth={}, rrDepth={}, heuristic={}, strategies={}]",
                           m_paths.depth().maxDepth, m_paths.depth().rrDepth,
                           m_paths.heuristic() == MISHeuristic::Power ? "power" : "balance",
                           !m_layerOf.empty());
    }

private:
    /// The longest paths (in scattering events) whose strategies the debug view shows.
    static constexpr int kLongestStrategyPath = 5;

    BidirectionalPaths m_paths;
    std::vector<std::string> m_layerNames;
    /// (s, t) → its weighted layer (Splat::layer); the unweighted one follows it.
    std::map<std::pair<int, int>, int> m_layerOf;
};

NORI_REGISTER_CLASS(BDPTIntegrator, "bdpt");

} // namespace
} // namespace nori
