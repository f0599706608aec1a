// Bidirectional path tracing (include/nori/bdpt.h, plugins/builtin/integrators/bdpt.cpp): each
// strategy alone is unbiased, the recursive MIS weights equal the ones computed from
// every strategy's density from scratch, light paths through glass carry flux (η²), the
// emission and camera densities are those their samplers draw, and renders keep the same
// bits for any thread count.
#include "testutil.h"

#include "app/renderpart.h"
#include <nori/bdpt.h>
#include <nori/bsdf.h>
#include <nori/camera.h>
#include <nori/emitter.h>
#include <nori/integrator.h>
#include <nori/parser.h>
#include <nori/pcg32.h>
#include <nori/proplist.h>
#include <nori/render.h>
#include <nori/sampler.h>
#include <nori/scene.h>
#include <nori/statistics.h>

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <map>

using namespace nori;
using namespace nori::testing;

namespace {

/// A dielectric whose refractions report η = 1: radiance is still scaled by 1/η² on
/// entering, but light paths can no longer undo it for flux (Veach 1997, §5.2), the bug of
/// an adjoint BSDF without its η² correction. The negative control of the glass test.
class DielectricWithoutAdjointEta : public BSDF {
public:
    explicit DielectricWithoutAdjointEta(const PropertyList &props)
        : m_glass(std::static_pointer_cast<BSDF>(
              NoriObjectFactory::createInstance("dielectric", EBSDF, props))) {}
    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        Color3f weight = m_glass->sample(bRec, sample);
        bRec.eta = 1.0f;
        return weight;
    }
    Color3f eval(const BSDFQueryRecord &bRec) const override { return m_glass->eval(bRec); }
    float pdf(const BSDFQueryRecord &bRec) const override { return m_glass->pdf(bRec); }
    std::string toString() const override { return "DielectricWithoutAdjointEta[]"; }

private:
    std::shared_ptr<BSDF> m_glass;
};
NORI_REGISTER_CLASS(DielectricWithoutAdjointEta, "test_dielectric_without_adjoint_eta");

/// The README's Cornell box (scenes/cbox), `sphere` the BSDF of its second sphere and
/// `inside` shapes added to it, at 32 × 32 pixels.
std::shared_ptr<Scene> cornellBox(const std::string &sphere, const std::string &inside = "") {
    const std::string directory = std::string(NORI_SOURCE_DIR) + "/scenes/cbox";
    std::string xml = R"(<scene><integrator type="path_mis"/>
        <sampler type="independent"><integer name="sampleCount" value="1"/></sampler>
        <camera type="perspective"><float name="fov" value="39"/>
            <integer name="width" value="32"/><integer name="height" value="32"/>
            <transform name="toWorld"><lookat origin="0, 1, 3.85" target="0, 1, 0" up="0, 1, 0"/>
            </transform></camera>
        <bsdf type="diffuse" id="white"><color name="albedo" value="0.73, 0.71, 0.68"/></bsdf>
        <mesh type="obj"><string name="filename" value="meshes/floor.obj"/><ref id="white"/></mesh>
        <mesh type="obj"><string name="filename" value="meshes/ceiling.obj"/><ref id="white"/></mesh>
        <mesh type="obj"><string name="filename" value="meshes/back.obj"/><ref id="white"/></mesh>
        <mesh type="obj"><string name="filename" value="meshes/left.obj"/>
            <bsdf type="diffuse"><color name="albedo" value="0.63, 0.065, 0.05"/></bsdf></mesh>
        <mesh type="obj"><string name="filename" value="meshes/right.obj"/>
            <bsdf type="diffuse"><color name="albedo" value="0.14, 0.45, 0.091"/></bsdf></mesh>
        <mesh type="obj"><string name="filename" value="meshes/light.obj"/>
            <bsdf type="diffuse"><color name="albedo" value="0"/></bsdf>
            <emitter type="area"><color name="radiance" value="17, 12, 4"/></emitter></mesh>
        <mesh type="sphere"><point name="center" value="-0.45, 0.35, -0.35"/>
            <float name="radius" value="0.35"/><ref id="white"/></mesh>
        <mesh type="sphere"><point name="center" value="0.45, 0.35, 0.3"/>
            <float name="radius" value="0.35"/>)" +
                      sphere + "</mesh>" + inside + "</scene>";
    return loadScene(xml, directory);
}

/// A path integrator with the given maxDepth and no Russian roulette.
std::shared_ptr<Integrator> pathTracer(int maxDepth) {
    PropertyList props;
    props.setInteger("maxDepth", maxDepth);
    props.setInteger("rrDepth", 1000);
    auto integrator = std::static_pointer_cast<Integrator>(
        NoriObjectFactory::createInstance("path_mis", NoriObject::EIntegrator, props));
    integrator->activate();
    return integrator;
}

/// Starts camera sample `index` at a film position uniform over the window [x0, x1) ×
/// [y0, y1) of pixels (the whole image by default) and returns its ray and weight.
Color3f startSample(const Scene &scene, Sampler &sampler, size_t index, Ray3f &ray,
                    const Point2f &from = Point2f(0.0f, 0.0f),
                    const Point2f &to = Point2f(32.0f, 32.0f)) {
    sampler.generate(Point2i(static_cast<int>(index % 4096), static_cast<int>(index / 4096)));
    const Point2f u = sampler.next2D();
    const Point2f film(from.x() + u.x() * (to.x() - from.x()),
                       from.y() + u.y() * (to.y() - from.y()));
    return scene.sampleCameraRay(ray, film, sampler.next2D());
}

/// Whether two means (with their standard errors) differ at the per-test level `alpha`
/// (two-sided; normal, the sample counts are large).
bool differ(const RunningMoments &a, const RunningMoments &b, double alpha, double &z) {
    const double se = std::sqrt(a.variance() / static_cast<double>(a.count) +
                                b.variance() / static_cast<double>(b.count));
    z = se > 0.0 ? (a.mean - b.mean) / se : 0.0;
    return 2.0 * (1.0 - studentTCdf(std::abs(z), 1e6)) < alpha;
}

/// Per camera sample, each strategy's unweighted value (own pixel and splats alike) of
/// BidirectionalPaths with maxDepth 3, and path_mis's light of each exact path length
/// (the difference of maxDepth L and L − 1 on the same random numbers), for the
/// strategies with s + t ≤ 5 that `compared` keeps (all by default), film positions
/// uniform over the window [from, to). `distort` may change a strategy's value (negative
/// controls).
struct StrategyMeans {
    std::map<std::pair<int, int>, RunningMoments> strategies;
    std::array<RunningMoments, 4> pathLengths;
};

StrategyMeans strategyMeans(Scene &scene, size_t samples,
                            const std::function<void(StrategySample &)> &distort = {},
                            const std::function<bool(int, int)> &compared = {},
                            const Point2f &from = Point2f(0.0f, 0.0f),
                            const Point2f &to = Point2f(32.0f, 32.0f)) {
    PathDepth depth;
    depth.maxDepth = 3;
    depth.rrDepth = 1000;
    const BidirectionalPaths paths(depth, MISHeuristic::Power);
    std::array<std::shared_ptr<Integrator>, 4> pathTracers;
    for (int length = 1; length < 4; ++length)
        pathTracers[length] = pathTracer(length);
    std::unique_ptr<Sampler> sampler = scene.getSampler()->clone();
    sampler->setSeed(11);
    StrategyMeans means;
    std::vector<Splat> splats;
    const Vector2i size = scene.getCamera()->getOutputSize();
    const double imageOverWindow =
        static_cast<double>(size.x()) * size.y() / ((to.x() - from.x()) * (to.y() - from.y()));
    for (size_t i = 0; i < samples; ++i) {
        Ray3f ray;
        std::map<std::pair<int, int>, double> values;
        const Color3f weight = startSample(scene, *sampler, i, ray, from, to);
        paths.estimate(scene, *sampler, ray, splats, [&](const StrategySample &strategy) {
            StrategySample copy = strategy;
            if (distort)
                distort(copy);
            if (!copy.splat) {
                values[{copy.s, copy.t}] += Color3f(weight * copy.unweighted).getLuminance();
                return;
            }
            // A splat lands anywhere on the image: it adds to the window's mean where it
            // lands inside, scaled by the image's area over the window's (the camera
            // samples are uniform over the window, the splats' positions over the image).
            if (copy.position.x() >= from.x() && copy.position.x() < to.x() &&
                copy.position.y() >= from.y() && copy.position.y() < to.y())
                values[{copy.s, copy.t}] += copy.unweighted.getLuminance() * imageOverWindow;
        });
        splats.clear();
        for (int s = 0; s <= 5; ++s)
            for (int t = 1; s + t <= 5; ++t)
                if (paths.allowed(s, t) && (!compared || compared(s, t)))
                    means.strategies[{s, t}].add(values[{s, t}]);
        // Length 0: the light the camera ray sees (path_mis takes maxDepth ≥ 1).
        startSample(scene, *sampler, i, ray, from, to);
        Intersection its;
        double previous = 0.0;
        if (scene.rayIntersect(ray, its) && its.shape->getEmitter())
            previous =
                Color3f(weight * its.shape->getEmitter()->eval(EmitterQueryRecord(ray.o, its)))
                    .getLuminance();
        means.pathLengths[0].add(previous);
        for (int length = 1; length < 4; ++length) {
            startSample(scene, *sampler, i, ray, from, to);
            const double light =
                Color3f(weight * pathTracers[length]->Li(&scene, sampler.get(), ray))
                    .getLuminance();
            means.pathLengths[length].add(light - previous);
            previous = light;
        }
    }
    return means;
}

/// The strategies whose mean differs from path_mis's of their path length, at an overall
/// significance of 1 % (Šidák over all strategies compared).
std::vector<std::string> disagreeing(const StrategyMeans &means) {
    const double alpha = sidakCorrection(0.01, static_cast<int>(means.strategies.size()));
    std::vector<std::string> found;
    for (const auto &[strategy, moments] : means.strategies) {
        const int length = strategy.first + strategy.second - 2;
        double z = 0.0;
        if (differ(moments, means.pathLengths.at(length), alpha, z))
            found.push_back(
                fmt::format("(s={}, t={}) z={:.2f}", strategy.first, strategy.second, z));
        UNSCOPED_INFO("(s=" << strategy.first << ", t=" << strategy.second << ") mean "
                            << moments.mean << " against path length " << length << ": "
                            << means.pathLengths.at(length).mean << ", z = " << z);
    }
    return found;
}

} // namespace

TEST_CASE("Each BDPT strategy alone is unbiased for its path length", "[bdpt][statistical]") {
    // A diffuse Cornell box, paths of 0 to 3 scattering events: every (s, t) with s + t ≤ 5,
    // unweighted, against path_mis's light of that exact length (Veach 1997, §10.2).
    const std::shared_ptr<Scene> scene =
        cornellBox(R"(<bsdf type="diffuse"><color name="albedo" value="0.5"/></bsdf>)");
    constexpr size_t kSamples = 60000;
    const StrategyMeans means = strategyMeans(*scene, kSamples);
    CHECK(means.strategies.size() == 13); // 1 + 3 + 4 + 5 strategies of 0 to 3 events
    CHECK(disagreeing(means).empty());

    SECTION("negative control: a camera importance without its 1/cos³θ") {
        // The light tracing strategies (t = 1) with We·cos/d² missing the film's
        // projection, as tests/planted/planted_importance.cpp plants it in lighttracer.
        const Camera &camera = *scene->getCamera();
        Ray3f axis;
        camera.sampleRay(axis, Point2f(16.0f, 16.0f), Point2f(0.5f, 0.5f));
        const StrategyMeans control = strategyMeans(*scene, kSamples, [&](StrategySample &sample) {
            if (!sample.splat)
                return;
            Ray3f toSplat;
            camera.sampleRay(toSplat, sample.position, Point2f(0.5f, 0.5f));
            const float cosTheta = axis.d.dot(toSplat.d);
            sample.unweighted *= cosTheta * cosTheta * cosTheta;
        });
        const std::vector<std::string> found = disagreeing(control);
        CAPTURE(found);
        CHECK(found.size() >= 2);
        for (const std::string &strategy : found)
            CHECK(strategy.find("t=1)") != std::string::npos);
    }
}

TEST_CASE("BDPT's next-event estimation chooses lights by the light tree, unbiased",
          "[bdpt][lighttree][statistical]") {
    // The diffuse Cornell box with two small sphere lights besides its own, of other
    // powers, low on the left and high on the right: the light tree's choice at a point
    // differs much from power's. The strategies s = 1 against path_mis's light of each
    // path length (1 to 3 scattering events).
    const std::shared_ptr<Scene> scene =
        cornellBox(R"(<bsdf type="diffuse"><color name="albedo" value="0.5"/></bsdf>)",
                   R"(<mesh type="sphere"><point name="center" value="-0.75, 0.25, 0.4"/>
                       <float name="radius" value="0.08"/>
                       <emitter type="area"><color name="radiance" value="30"/></emitter></mesh>
                   <mesh type="sphere"><point name="center" value="0.7, 1.6, -0.5"/>
                       <float name="radius" value="0.05"/>
                       <emitter type="area"><color name="radiance" value="10, 20, 40"/></emitter>
                   </mesh>)");
    constexpr size_t kSamples = 60000;
    const auto nextEvent = [](int s, int) { return s == 1; };
    const StrategyMeans means = strategyMeans(*scene, kSamples, {}, nextEvent);
    CHECK(means.strategies.size() == 3);
    CHECK(disagreeing(means).empty());

    SECTION("negative control: the light chosen by the tree, divided by its pmf by power") {
        const StrategyMeans control = strategyMeans(
            *scene, kSamples,
            [&](StrategySample &sample) {
                if (sample.s == 1 && sample.light)
                    sample.unweighted *= sample.lightPmf / scene->emitterPmf(sample.light);
            },
            nextEvent);
        const std::vector<std::string> found = disagreeing(control);
        CAPTURE(found);
        CHECK(found.size() >= 2);
    }
}

namespace {

/// Every strategy's density of the path (s, t) made, computed from scratch from the
/// vertices' positions, BSDFs, the lights and the camera (no forward or reverse densities
/// kept by the subpaths), and the weight of (s, t) among the strategies that can make the
/// path: p_s^β / Σ p_i^β (β = 2: the power heuristic, 1: the balance heuristic).
float bruteForceWeight(const Scene &scene, const std::vector<PathVertex> &light, int s,
                       const std::vector<PathVertex> &camera, int t, const PathVertex &sampled,
                       const CameraLink &link, double exponent) {
    std::vector<PathVertex> x;
    x.reserve(static_cast<size_t>(s) + static_cast<size_t>(t));
    for (int i = 0; i < s; ++i)
        x.push_back(s == 1 ? sampled : light[i]);
    for (int i = t - 1; i >= 0; --i)
        x.push_back(t == 1 ? sampled : camera[i]);
    if (t == 1 && link.traced)
        x[s - 1].its = link.seen;
    const int k = s + t;
    if (k == 2)
        return 1.0f;
    // The joined vertices scattered by evaluation, not by a delta lobe.
    if (s > 0)
        x[s - 1].delta = false;
    x[s].delta = false;
    // Densities of each vertex as the light side and as the camera side samples it; a
    // delta event's density is a Dirac factor that every strategy crossing it shares,
    // times the geometry term of its edge (Veach 1997, §10.3.5).
    std::vector<double> fromLight(k, 1.0), fromCamera(k, 1.0);
    // G(a, b) = |cos θa||cos θb|/d²: a cosine only where there is a surface, and toward a
    // light at infinity a density per solid angle (no cosine there, no distance).
    auto geometry = [](const PathVertex &a, const PathVertex &b) {
        const Vector3f w = directionBetween(a, b);
        double g = (a.onSurface() ? std::abs(a.n.dot(w)) : 1.0) *
                   (b.onSurface() ? std::abs(b.n.dot(w)) : 1.0);
        if (!a.atInfinity && !b.atInfinity)
            g /= static_cast<double>((b.p - a.p).squaredNorm());
        return g;
    };
    for (int j = 0; j < k - 1; ++j) {
        if (j == 0)
            fromLight[j] = BidirectionalPaths::pdfLightOrigin(scene, x[0], x[1]);
        else if (j == 1)
            fromLight[j] = BidirectionalPaths::pdfLight(scene, x[0], x[1]);
        else if (x[j - 1].delta)
            fromLight[j] = geometry(x[j - 1], x[j]);
        else
            fromLight[j] = BidirectionalPaths::pdfToward(scene, x[j - 1], &x[j - 2], x[j]);
        if (j == k - 2)
            fromCamera[j] = BidirectionalPaths::pdfToward(scene, x[k - 1], nullptr, x[j]);
        else if (x[j + 1].delta)
            fromCamera[j] = geometry(x[j + 1], x[j]);
        else
            fromCamera[j] = BidirectionalPaths::pdfToward(scene, x[j + 1], &x[j + 2], x[j]);
    }
    // Strategy 1 chooses the light of x_0 as next-event estimation does at x_1 (the light
    // tree's pmf there), where the light subpaths choose it by power: its density is
    // fromLight[0] times the ratio of the two (summed over the lights at infinity, whose
    // directions add).
    double nextEventRatio = 1.0;
    if (x[1].kind == PathVertex::Kind::Surface && x[0].isLight()) {
        auto byTree = [&](const Emitter *emitter) {
            return static_cast<double>(scene.emitterPmf(x[1].p, x[1].its.shFrame.n, emitter));
        };
        auto byPower = [&](const Emitter *emitter) {
            return static_cast<double>(scene.emitterPmf(emitter));
        };
        double tree = 0.0, power = 0.0;
        if (x[0].atInfinity) {
            EmitterQueryRecord lRec;
            lRec.wi = directionBetween(x[1], x[0]);
            for (const Emitter *emitter : scene.getInfiniteEmitters()) {
                tree += byTree(emitter) * emitter->pdf(lRec);
                power += byPower(emitter) * emitter->pdf(lRec);
            }
        } else {
            tree = byTree(x[0].emitter);
            power = byPower(x[0].emitter);
        }
        nextEventRatio = power > 0.0 ? tree / power : 1.0;
    }
    // Strategy i takes x_0..x_{i−1} from the light and x_i..x_{k−1} from the camera.
    auto density = [&](int i) {
        double p = i == 1 ? nextEventRatio : 1.0;
        for (int j = 0; j < i; ++j)
            p *= fromLight[j];
        for (int j = i; j < k - 1; ++j)
            p *= fromCamera[j];
        return p;
    };
    auto possible = [&](int i) {
        if (i == 1 && k - i == 1)
            return false;
        if (x[i].delta)
            return false;
        return i > 0 ? !x[i - 1].delta : !x[0].isDeltaLight() && x[0].isLight();
    };
    const double own = std::pow(density(s), exponent);
    double sum = 0.0;
    for (int i = 0; i < k; ++i)
        if (possible(i))
            sum += std::pow(density(i), exponent);
    return sum > 0.0 ? static_cast<float>(own / sum) : 0.0f;
}

} // namespace

TEST_CASE("BDPT's recursive MIS weights equal the weights of every strategy's density", "[bdpt]") {
    // Random paths in scenes with glass, a mirror, a rough metal, area, point, spot and
    // environment lights; every strategy that made a contribution. The brute-force weights
    // sum to 1 over the strategies that can make a path by construction, so agreement
    // shows that the recursive ones do too.
    const std::string lights = GENERATE(
        std::string(),
        std::string(R"(<emitter type="point"><point name="position" value="0.2, 1.5, 0.5"/>
            <color name="intensity" value="2"/></emitter>
            <emitter type="spot"><point name="position" value="-0.5, 1.8, 1"/>
            <point name="target" value="0, 0, 0"/><color name="intensity" value="5"/></emitter>)"),
        std::string(R"(<emitter type="constant"><color name="radiance" value="0.3"/></emitter>)"));
    const std::shared_ptr<Scene> scene =
        cornellBox(R"(<bsdf type="dielectric"/>)",
                   lights + R"(<mesh type="sphere"><point name="center" value="-0.3, 1.2, 0"/>
            <float name="radius" value="0.2"/><bsdf type="mirror"/></mesh>
            <mesh type="sphere"><point name="center" value="0.4, 1.3, -0.4"/>
            <float name="radius" value="0.2"/><bsdf type="roughconductor">
            <float name="alpha" value="0.3"/></bsdf></mesh>)");
    PathDepth depth;
    depth.maxDepth = 6;
    for (const MISHeuristic heuristic : {MISHeuristic::Power, MISHeuristic::Balance}) {
        const BidirectionalPaths paths(depth, heuristic);
        std::unique_ptr<Sampler> sampler = scene->getSampler()->clone();
        sampler->setSeed(5);
        std::vector<PathVertex> camera, light;
        size_t compared = 0;
        for (size_t i = 0; i < 3000; ++i) {
            Ray3f ray;
            startSample(*scene, *sampler, i, ray);
            paths.traceCameraSubpath(*scene, *sampler, ray, camera);
            paths.traceLightSubpath(*scene, *sampler, light);
            for (int t = 1; t <= static_cast<int>(camera.size()); ++t) {
                for (int s = 0; s <= static_cast<int>(light.size()); ++s) {
                    if (!paths.allowed(s, t))
                        continue;
                    PathVertex sampled;
                    CameraLink link;
                    const StrategySample strategy =
                        paths.connect(*scene, light, s, camera, t, sampled, link);
                    if ((strategy.unweighted == 0.0f).all())
                        continue;
                    const float weight =
                        paths.misWeight(*scene, light, s, camera, t, sampled, link);
                    const float expected =
                        bruteForceWeight(*scene, light, s, camera, t, sampled, link,
                                         heuristic == MISHeuristic::Power ? 2.0 : 1.0);
                    INFO("sample " << i << ", strategy (s=" << s << ", t=" << t << ")");
                    REQUIRE(weight >= 0.0f);
                    REQUIRE(weight <= 1.0f + 1e-5f);
                    // Products of up to a dozen float ratios against double: at most
                    // 5.5e-7 relative measured, so 1e-5.
                    CHECK(weight == Approx(expected).epsilon(1e-5).margin(1e-6));
                    ++compared;
                }
            }
        }
        CHECK(compared > 5000);
    }
}

namespace {

/// A camera under glass: inside a large sphere of `glass` over a diffuse ground (a sphere)
/// lit by a constant environment, so that every light path enters the glass before it
/// reaches the ground. The strategies that can make every path the camera sees on the
/// ground, s = 0 and light tracing (t = 1), each against path_mis's light of its length,
/// over the window of the image where the ground is seen.
std::vector<std::string> disagreeingUnderGlass(const std::string &glass) {
    const std::shared_ptr<Scene> scene = loadScene(
        R"(<scene><integrator type="path_mis"/>
        <sampler type="independent"><integer name="sampleCount" value="1"/></sampler>
        <camera type="perspective"><float name="fov" value="50"/>
            <integer name="width" value="32"/><integer name="height" value="32"/>
            <transform name="toWorld"><lookat origin="0, 1, 2.5" target="0, 0.2, 0" up="0, 1, 0"/>
            </transform></camera>
        <emitter type="constant"><color name="radiance" value="1"/></emitter>
        <mesh type="sphere"><point name="center" value="0, -3, 0"/><float name="radius" value="3"/>
            <bsdf type="diffuse"><color name="albedo" value="0.6"/></bsdf></mesh>
        <mesh type="sphere"><float name="radius" value="4"/>)" +
        glass + "</mesh></scene>");
    const StrategyMeans means = strategyMeans(
        *scene, 40000, {}, [](int s, int t) { return s + t >= 4 && (s == 0 || t == 1); },
        Point2f(10.0f, 23.0f), Point2f(22.0f, 32.0f));
    return disagreeing(means);
}

} // namespace

TEST_CASE("BDPT's light paths carry flux through glass (η²)", "[bdpt][statistical]") {
    // Light tracing under glass carries the light subpath's flux through a refraction: a
    // BSDF sample scales radiance by 1/η² there, and flux must not be (Veach 1997, §5.2).
    const std::vector<std::string> found = disagreeingUnderGlass(R"(<bsdf type="dielectric"/>)");
    CAPTURE(found);
    CHECK(found.empty());

    SECTION("negative control: the adjoint BSDF without its η² correction") {
        const std::vector<std::string> forgetful =
            disagreeingUnderGlass(R"(<bsdf type="test_dielectric_without_adjoint_eta"/>)");
        CAPTURE(forgetful);
        // Light tracing through one refraction, (3, 1), is off by η² = 2.26 (z = −7.4 with
        // this seed); the longer (4, 1) is noisier than the 1 % level can tell.
        REQUIRE_FALSE(forgetful.empty());
        CHECK(forgetful.front().find("(s=3, t=1)") == 0);
        for (const std::string &strategy : forgetful)
            CHECK(strategy.find("t=1)") != std::string::npos);
    }
}

TEST_CASE("Lights give the densities their photons are drawn with", "[bdpt][emitters]") {
    const std::string emitters = GENERATE(
        std::string(R"(<mesh type="sphere"><point name="center" value="0, 1, 0"/>
            <float name="radius" value="0.3"/>
            <emitter type="area"><color name="radiance" value="2"/></emitter></mesh>)"),
        std::string(R"(<emitter type="point"><point name="position" value="0, 1, 0"/>
            <color name="intensity" value="1"/></emitter>)"),
        std::string(R"(<emitter type="spot"><point name="position" value="0, 1, 0"/>
            <point name="target" value="0, 0, 0"/><float name="cutoffAngle" value="40"/>
            <float name="beamWidth" value="25"/><color name="intensity" value="1"/></emitter>)"),
        std::string(R"(<emitter type="directional"><vector name="direction" value="1, -2, 0"/>
            </emitter>)"),
        std::string(R"(<emitter type="distantdisk"><float name="thetaA" value="10"/></emitter>)"),
        std::string(R"(<emitter type="constant"><color name="radiance" value="1"/></emitter>)"));
    const std::shared_ptr<Scene> scene =
        loadScene(R"(<scene><integrator type="path_mis"/><camera type="perspective"/>)" + emitters +
                  R"(<mesh type="sphere"><float name="radius" value="0.5"/>
        <bsdf type="diffuse"/></mesh></scene>)");
    const Emitter &emitter = *scene->getEmitters().front();
    PCG32 random(9, 1);
    for (int i = 0; i < 200; ++i) {
        EmissionSample emission;
        const Point2f position(random.nextFloat(), random.nextFloat());
        const Point2f direction(random.nextFloat(), random.nextFloat());
        if ((emitter.sampleEmission(emission, position, direction) == 0.0f).all())
            continue;
        const EmissionDensity density =
            emitter.emissionDensity(emission.p, emission.n, emission.ray.d.normalized());
        INFO(emitter.toString());
        // The same densities from the sampled and from the recomputed world direction: float
        // rounding, at most 1.05e-5 relative for the direction in this test (measured), so
        // 1e-4; the positions agree to 1e-5.
        CHECK(density.position == Approx(emission.density.position).epsilon(1e-5));
        CHECK(density.direction == Approx(emission.density.direction).epsilon(1e-4));
        CHECK(density.position > 0.0f);
        CHECK(density.direction > 0.0f);
    }
}

TEST_CASE("The camera's direction density is its importance at unit distance", "[bdpt][camera]") {
    // pdfDirection = 1/(A cos³θ) for the pinhole and the thin lens (PBR 3rd ed. §16.1.1), the
    // importance connect() gives per unit of d², and zero outside the image.
    for (const std::string &lens : {std::string(), std::string(R"(<float name="apertureRadius"
            value="0.2"/><float name="focalDistance" value="3"/>)")}) {
        const auto camera = std::dynamic_pointer_cast<Camera>(loadFromXMLString(
            R"(<camera type="perspective"><integer name="width" value="64"/>
            <integer name="height" value="48"/><float name="fov" value="50"/>
            <transform name="toWorld"><lookat origin="0.3, 1, 4" target="0, 0.2, 0" up="0, 1, 0"/>
            </transform>)" +
                lens + "</camera>",
            "."));
        PCG32 random(4, 2);
        for (int i = 0; i < 500; ++i) {
            const Point2f film(64.0f * random.nextFloat(), 48.0f * random.nextFloat());
            const Point2f aperture(random.nextFloat(), random.nextFloat());
            Ray3f ray;
            camera->sampleRay(ray, film, aperture);
            const float distance = 1.0f + 4.0f * random.nextFloat();
            CameraConnection connection;
            REQUIRE(camera->connect(ray(distance), aperture, connection));
            INFO("lens: " << lens << ", film position " << film.x() << ", " << film.y());
            CHECK(camera->pdfDirection(ray.o, ray.d) ==
                  Approx(connection.importance * connection.distance * connection.distance)
                      .epsilon(1e-5));
        }
        Ray3f ray;
        camera->sampleRay(ray, Point2f(32.0f, 24.0f), Point2f(0.5f, 0.5f));
        CHECK(camera->pdfDirection(ray.o, -ray.d) == 0.0f);
    }
}

TEST_CASE("A BDPT image is the same for any thread count", "[bdpt][render]") {
    LoadOptions options({{"integrator", "bdpt"}, {"size", "48"}, {"spp", "8"}});
    const auto scene = std::dynamic_pointer_cast<Scene>(
        loadFromXML(std::string(NORI_SOURCE_DIR) + "/scenes/cbox/cbox.xml", options));
    const RenderResult one = renderScene(*scene, quietOptions(1));
    const RenderResult two = renderScene(*scene, quietOptions(2));
    CHECK(identicalImages(one.image, two.image));
    CHECK(one.layers.channels().at("G").maxCoeff() > 0.0f);
}

TEST_CASE("BDPT says what it cannot render", "[bdpt]") {
    const std::string box = R"(<integrator type="bdpt">{}</integrator>
        <sampler type="independent"><integer name="sampleCount" value="1"/></sampler>
        <mesh type="sphere"><float name="radius" value="1"/>{}
            <emitter type="area"><color name="radiance" value="1"/></emitter></mesh>
        <camera type="perspective"><integer name="width" value="4"/>
        <integer name="height" value="4"/><transform name="toWorld">
        <lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform></camera>)";
    const auto render = [](const std::string &body) {
        std::shared_ptr<Scene> scene = loadScene("<scene>" + body + "</scene>");
        renderScene(*scene, quietOptions(1));
    };
    CHECK_THAT(errorOf([&] { render(fmt::format(box, "", "")); }), Catch::Equals(""));
    CHECK_THAT(errorOf([&] {
                   render(fmt::format(box, "", R"(<medium type="homogeneous" name="interior"/>)"));
               }),
               Catch::Contains("bdpt") && Catch::Contains("participating media"));
    CHECK_THAT(errorOf([&] {
                   render(fmt::format(box, R"(<string name="heuristic" value="cubic"/>)", ""));
               }),
               Catch::Contains("bdpt") && Catch::Contains("'heuristic'") &&
                   Catch::Contains("cubic"));
}

TEST_CASE("BDPT's strategies debug view: a layer per strategy, summing to the image",
          "[bdpt][render]") {
    // Veach 1997, figure 10.3: each (s, t) weighted and unweighted; the weighted layers of
    // all strategies add up to the image (here every path has at most 2 events).
    const auto scene = std::dynamic_pointer_cast<Scene>(loadScene(
        R"(<scene><integrator type="bdpt"><boolean name="strategies" value="true"/>
            <integer name="maxDepth" value="2"/></integrator>
        <sampler type="independent"><integer name="sampleCount" value="4"/></sampler>
        <camera type="perspective"><float name="fov" value="39"/>
            <integer name="width" value="24"/><integer name="height" value="24"/>
            <transform name="toWorld"><lookat origin="0, 1, 3.85" target="0, 1, 0" up="0, 1, 0"/>
            </transform></camera>
        <mesh type="obj"><string name="filename" value="meshes/floor.obj"/><bsdf type="diffuse"/></mesh>
        <mesh type="obj"><string name="filename" value="meshes/back.obj"/><bsdf type="diffuse"/></mesh>
        <mesh type="obj"><string name="filename" value="meshes/light.obj"/>
            <emitter type="area"><color name="radiance" value="10"/></emitter></mesh>
        <mesh type="sphere"><point name="center" value="0.45, 0.35, 0.3"/>
            <float name="radius" value="0.35"/><bsdf type="dielectric"/></mesh></scene>)",
        std::string(NORI_SOURCE_DIR) + "/scenes/cbox"));
    const RenderResult result = renderScene(*scene, quietOptions(2));
    const std::vector<std::string> expected = {"s0t2", "s0t3", "s1t2", "s2t1",
                                               "s0t4", "s1t3", "s2t2", "s3t1"};
    const auto &channels = result.layers.channels();
    LayeredImage::Channel sum = LayeredImage::Channel::Zero(24, 24);
    for (const std::string &strategy : expected) {
        INFO(strategy);
        REQUIRE(channels.count(strategy + ".G") == 1);
        REQUIRE(channels.count(strategy + ".unweighted.G") == 1);
        sum += channels.at(strategy + ".G");
    }
    CHECK(channels.count("s1t1.G") == 0);
    CHECK(channels.count("s0t5.G") == 0);
    const LayeredImage::Channel &image = channels.at("G");
    CHECK(image.maxCoeff() > 0.0f);
    CHECK((sum - image).abs().maxCoeff() <= 1e-4f * image.maxCoeff());

    SECTION("and a render split in parts merges to the same layers") {
        // The same sums in another order: every layer within float rounding, 1e-5 of its
        // brightest pixel (a pixel's camera samples reach it through the 5×5 footprint of
        // the Gaussian filter, 100 terms at 4 spp, (n − 1)·2⁻²⁴ ≈ 6e-6, and its splats are
        // fewer; measured 2.9e-7); a part left out moves some pixel by as much as the
        // brightest (measured 1).
        TempDir dir;
        std::vector<std::string> files;
        for (int k = 1; k <= 2; ++k) {
            const RenderResult part =
                renderPart(*scene, quietOptions(2), {k, 2}, "0123456789abcdef", "box");
            files.push_back((dir.path() / fmt::format("part{}.exr", k)).string());
            part.layers.saveEXR(files.back());
        }
        const auto worstDifference = [&](const LayeredImage &merged) {
            double worst = 0.0;
            for (const std::string &strategy : expected)
                for (const std::string &layer : {strategy + ".G", strategy + ".unweighted.G"}) {
                    INFO(layer);
                    REQUIRE(merged.channels().count(layer) == 1);
                    const LayeredImage::Channel &single = channels.at(layer);
                    if (single.maxCoeff() > 0.0f)
                        worst = std::max(
                            worst, double((merged.channels().at(layer) - single).abs().maxCoeff() /
                                          single.maxCoeff()));
                }
            return worst;
        };
        const double merged = worstDifference(mergeParts(files, false).image);
        const double partMissing = worstDifference(mergeParts({files[0]}, true).image);
        CHECK(merged < 1e-5);
        CHECK(partMissing > 1e-1);
        WARN("strategy layers, merged against single: " << merged
                                                        << " of the brightest pixel; "
                                                           "a part missing: "
                                                        << partMissing);
    }
}
