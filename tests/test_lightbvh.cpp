// The light tree (lightbvh.h, lightbounds.h): cone unions hold both cones; at any point,
// the probabilities of the lights sum to at most one, sample() draws each light as often
// as pmf() says (χ², with a control that claims power-proportional choice and is
// rejected) and reports that same pmf; a light that can reach a point is never given
// probability zero there (no bias), one that cannot gets none; and a scene of many
// lights renders the same with the tree as with power selection.
#include "testing/agreement.h"
#include "testutil.h"

#include <nori/emitter.h>
#include <nori/lightbvh.h>
#include <nori/pcg32.h>
#include <nori/scene.h>
#include <nori/statistics.h>
#include <nori/warp.h>

#include <catch2/catch.hpp>

#include <fstream>

using namespace nori;
using namespace nori::testing;

namespace {

/// A light that is only its bounds and power: what the tree sees of an emitter.
class BoundsOnlyLight : public Emitter {
public:
    BoundsOnlyLight(std::optional<LightBounds> bounds, float power)
        : m_bounds(std::move(bounds)), m_power(power) {}
    Color3f sample(EmitterQueryRecord &, const Point2f &) const override { return Color3f(0.0f); }
    Color3f eval(const EmitterQueryRecord &) const override { return Color3f(0.0f); }
    float pdf(const EmitterQueryRecord &) const override { return 0.0f; }
    Color3f getPower() const override { return Color3f(m_power); }
    std::optional<LightBounds> lightBounds() const override { return m_bounds; }
    std::string toString() const override { return "BoundsOnlyLight[]"; }

private:
    std::optional<LightBounds> m_bounds;
    float m_power;
};

/// A one-sided triangle light: its box, its normal (θo = 0), emission up to 90°.
struct TriangleLight {
    Point3f p0, p1, p2;
    Vector3f normal;
    LightBounds bounds(float power) const {
        LightBounds result;
        result.bounds = BoundingBox3f(p0);
        result.bounds.expandBy(p1);
        result.bounds.expandBy(p2);
        result.w = normal;
        result.cosThetaO = 1.0f;
        result.cosThetaE = 0.0f;
        result.phi = power;
        return result;
    }
};

TriangleLight randomTriangle(PCG32 &rng) {
    const Point3f center = randomPoint(rng, 5.0f);
    const float size = 0.05f + 0.5f * rng.nextFloat();
    TriangleLight t{center + size * randomDirection(rng), center + size * randomDirection(rng),
                    center + size * randomDirection(rng), Vector3f::Zero()};
    t.normal = (t.p1 - t.p0).cross(t.p2 - t.p0).normalized();
    return t;
}

/// 120 lights of powers over two decades: triangles, omnidirectional points (θo = π),
/// spots (a cone of emission about one axis), and two lights without bounds.
std::vector<std::shared_ptr<Emitter>> mixedLights(PCG32 &rng) {
    std::vector<std::shared_ptr<Emitter>> lights;
    for (int i = 0; i < 120; ++i) {
        const float power = std::exp(std::log(0.1f) + std::log(100.0f) * rng.nextFloat());
        LightBounds bounds;
        switch (i % 3) {
        case 0:
            bounds = randomTriangle(rng).bounds(power);
            break;
        case 1:
            bounds.bounds = BoundingBox3f(randomPoint(rng, 5.0f));
            bounds.cosThetaO = -1.0f;
            bounds.phi = power;
            break;
        default:
            bounds.bounds = BoundingBox3f(randomPoint(rng, 5.0f));
            bounds.w = randomDirection(rng);
            bounds.cosThetaO = 1.0f;
            bounds.cosThetaE = std::cos(0.2f + rng.nextFloat());
            bounds.phi = power;
        }
        lights.push_back(std::make_shared<BoundsOnlyLight>(bounds, power));
    }
    lights.push_back(std::make_shared<BoundsOnlyLight>(std::nullopt, 3.0f));
    lights.push_back(std::make_shared<BoundsOnlyLight>(std::nullopt, 0.5f));
    return lights;
}

} // namespace

TEST_CASE("A union of direction cones holds every direction of both", "[lights][lighttree]") {
    PCG32 rng;
    for (int trial = 0; trial < 2000; ++trial) {
        const DirectionCone a(randomDirection(rng), 2.0f * rng.nextFloat() - 1.0f);
        const DirectionCone b(randomDirection(rng), 2.0f * rng.nextFloat() - 1.0f);
        const DirectionCone both = coneUnion(a, b);
        for (int k = 0; k < 50; ++k) {
            const Vector3f v = randomDirection(rng);
            if (a.contains(v) || b.contains(v)) {
                CAPTURE(trial, a.cosTheta, b.cosTheta, both.cosTheta, both.w.dot(v));
                REQUIRE(both.w.dot(v) >= both.cosTheta - 1e-5f);
            }
        }
    }
    CHECK(coneUnion(DirectionCone(Vector3f(0, 0, 1)), DirectionCone(Vector3f(0, 0, -1))).cosTheta ==
          -1.0f);
}

TEST_CASE("The light tree draws each light as often as its pmf says (chi-square)",
          "[lights][lighttree]") {
    PCG32 rng(7, 1);
    const auto lights = mixedLights(rng);
    LightBVH tree;
    tree.build(lights);
    CHECK(tree.unboundedCount() == 2);
    float totalPower = 0.0f;
    for (const auto &light : lights)
        totalPower += light->getPower().getLuminance();

    const int points = 8;
    const size_t samples = 400000;
    const double significance = sidakCorrection(0.01, points);
    for (int point = 0; point < points; ++point) {
        const Point3f p = randomPoint(rng, 6.0f);
        const Normal3f n = point % 2 == 0 ? Normal3f(randomDirection(rng)) : Normal3f::Zero();
        CAPTURE(point);
        // Expected counts: one cell per light, and one for "no light" (1 − Σ pmf).
        std::vector<double> expected(lights.size() + 1, 0.0), byPower(lights.size() + 1, 0.0),
            observed(lights.size() + 1, 0.0);
        double sum = 0.0;
        for (size_t i = 0; i < lights.size(); ++i) {
            const float pmf = tree.pmf(p, n, lights[i].get());
            sum += pmf;
            expected[i] = pmf * static_cast<double>(samples);
            byPower[i] = lights[i]->getPower().getLuminance() / totalPower * double(samples);
        }
        REQUIRE(sum <= 1.0 + 1e-5);
        CHECK(sum > 0.5); // most of the mass reaches some light
        expected.back() = std::max(0.0, 1.0 - sum) * static_cast<double>(samples);
        for (size_t s = 0; s < samples; ++s) {
            float u = rng.nextFloat(), pmf = 0.0f;
            const Emitter *chosen = tree.sample(p, n, u, pmf);
            if (!chosen) {
                observed.back() += 1.0;
                continue;
            }
            const auto index = static_cast<size_t>(
                std::find_if(lights.begin(), lights.end(),
                             [chosen](const auto &l) { return l.get() == chosen; }) -
                lights.begin());
            observed[index] += 1.0;
            if (s < 2000) // the pmf sample() reports is pmf()'s
                REQUIRE(pmf == Approx(tree.pmf(p, n, chosen)).epsilon(1e-5));
        }
        const ChiSquareResult result = pearsonChiSquareTest(observed, expected, 5.0, significance);
        INFO(result.message);
        CHECK(result.passed);
        // The control: the same draws against the power-proportional choice.
        CHECK_FALSE(pearsonChiSquareTest(observed, byPower, 5.0, significance).passed);
    }
}

TEST_CASE("The light tree gives a light that can reach a point a positive probability",
          "[lights][lighttree]") {
    // One-sided triangles: every point in front of a triangle's plane is lit by all of
    // it, so its probability there must not be zero (that would be bias); behind every
    // point of it, the light is never chosen.
    PCG32 rng(11, 1);
    std::vector<std::shared_ptr<Emitter>> lights;
    std::vector<TriangleLight> triangles;
    for (int i = 0; i < 200; ++i) {
        triangles.push_back(randomTriangle(rng));
        const float power = 0.1f + rng.nextFloat();
        lights.push_back(std::make_shared<BoundsOnlyLight>(triangles.back().bounds(power), power));
    }
    LightBVH tree;
    tree.build(lights);
    int front = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        const Point3f p = randomPoint(rng, 7.0f);
        const Normal3f n = trial % 2 == 0 ? Normal3f(randomDirection(rng)) : Normal3f::Zero();
        for (size_t i = 0; i < triangles.size(); ++i) {
            const TriangleLight &t = triangles[i];
            const float side0 = (p - t.p0).dot(t.normal), side1 = (p - t.p1).dot(t.normal),
                        side2 = (p - t.p2).dot(t.normal);
            CAPTURE(trial, i);
            if (std::min({side0, side1, side2}) > 1e-3f) {
                ++front;
                REQUIRE(tree.pmf(p, n, lights[i].get()) > 0.0f);
            }
        }
    }
    // A lone light seen from behind: no choice, and pmf 0.
    LightBVH lone;
    lone.build({lights[0]});
    const TriangleLight &t = triangles[0];
    const Point3f behindPoint = t.p0 - 2.0f * t.normal;
    float u = 0.5f, pmf = 1.0f;
    CHECK(lone.sample(behindPoint, Normal3f::Zero(), u, pmf) == nullptr);
    CHECK(pmf == 0.0f);
    CHECK(lone.pmf(behindPoint, Normal3f::Zero(), lights[0].get()) == 0.0f);
    CHECK(front > 10000);
}

namespace {

/// 48 small lights (spheres and one-sided triangles facing random ways) over a floor
/// with a box, as scripts/make_many_lights.py writes them larger, rendered at 32 × 32
/// with path_mis; the lights chosen by `lightSampler`, their radiance times `scale`.
AgreementScene manyLights(const std::string &lightSampler, float scale) {
    AgreementScene scene;
    scene.name = "many-lights-" + lightSampler;
    scene.files["floor.obj"] = [](const std::string &path) {
        std::ofstream(path) << "v -4 0 -4\nv -4 0 4\nv 4 0 4\nv 4 0 -4\nf 1 2 3\nf 1 3 4\n";
    };
    scene.files["triangle.obj"] = [](const std::string &path) {
        std::ofstream(path) << "v -0.5 -0.29 0\nv 0.5 -0.29 0\nv 0 0.58 0\nf 1 2 3\n";
    };
    std::string body = fmt::format(R"(<string name="lightSampler" value="{}"/>
        <camera type="perspective"><float name="fov" value="60"/>
            <integer name="width" value="32"/> <integer name="height" value="32"/>
            <transform name="toWorld"><lookat origin="0, 0.5, 4" target="0, 0, 3.5" up="0, 1, 0"/></transform>
        </camera>
        <mesh type="obj"><string name="filename" value="floor.obj"/>
            <bsdf type="diffuse"><color name="albedo" value="0.6"/></bsdf></mesh>
        <mesh type="sphere"><point name="center" value="0.5, 0.4, 1.5"/>
            <float name="radius" value="0.4"/>
            <bsdf type="diffuse"><color name="albedo" value="0.5, 0.3, 0.2"/></bsdf></mesh>)",
                                   lightSampler);
    PCG32 rng(3, 1);
    for (int i = 0; i < 48; ++i) {
        const float power = scale * std::exp(std::log(0.05f) + std::log(100.0f) * rng.nextFloat());
        const Point3f at(-3.5f + 7.0f * rng.nextFloat(), 0.6f + 1.5f * rng.nextFloat(),
                         -3.5f + 7.0f * rng.nextFloat());
        if (i % 2 == 0) {
            const float radius = 0.03f + 0.05f * rng.nextFloat();
            body += fmt::format(R"(<mesh type="sphere"><point name="center" value="{}, {}, {}"/>
                <float name="radius" value="{}"/>
                <emitter type="area"><color name="radiance" value="{}"/></emitter></mesh>)",
                                at.x(), at.y(), at.z(), radius,
                                power / (kPi * 4.0f * kPi * radius * radius));
        } else {
            const Vector3f axis = randomDirection(rng);
            const float angle = 360.0f * rng.nextFloat(), edge = 0.1f + 0.15f * rng.nextFloat();
            body += fmt::format(R"(<mesh type="obj"><string name="filename" value="triangle.obj"/>
                <transform name="toWorld"><scale value="{}"/>
                    <rotate axis="{}, {}, {}" angle="{}"/><translate value="{}, {}, {}"/></transform>
                <emitter type="area"><color name="radiance" value="{}"/></emitter></mesh>)",
                                edge, axis.x(), axis.y(), axis.z(), angle, at.x(), at.y(), at.z(),
                                power / (kPi * 0.433f * edge * edge));
        }
    }
    scene.body = body;
    Estimator pathMIS;
    pathMIS.label = "path_mis";
    pathMIS.integrator = R"(<integrator type="path_mis"/>)";
    pathMIS.samplesPerPixel = 64;
    scene.estimators = {pathMIS};
    return scene;
}

} // namespace

TEST_CASE("Many lights chosen by the light tree light a floor as lights chosen by power",
          "[lights][lighttree][agreement]") {
    // The control: every light 2 % brighter (more at reduced test counts), chosen by the
    // tree, disagrees.
    const auto brighter = static_cast<float>(1.0 + scaledPlantedBias(0.02));
    const VariantAgreement result =
        compareVariant(manyLights("power", 1.0f), manyLights("bvh", 1.0f),
                       manyLights("bvh", brighter), AgreementSettings());
    REQUIRE(result.variant.size() == 1);
    INFO("tree against power, " << result.summary(0));
    CHECK(result.variant[0].agrees);
    CHECK_FALSE(result.control[0].agrees);
}
