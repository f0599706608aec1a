// The render loop and the first integrators: determinism across thread counts, the
// normals integrator against the analytic sphere, invalid samples, cancellation.
#include <nori/parser.h>
#include <nori/pcg32.h>
#include <nori/render.h>
#include <nori/scene.h>

#include "testutil.h"

#include <catch2/catch.hpp>

using namespace nori;
using nori::testing::loadScene;
using nori::testing::quietOptions;

namespace {

/// A value chosen by the ray direction: NaN, negative, infinite or 1.
Color3f invalidRadiance(const Ray3f &ray) {
    if (ray.d.x() > 0.2f)
        return Color3f(std::numeric_limits<float>::quiet_NaN());
    if (ray.d.x() < -0.2f)
        return Color3f(1.0f, -1.0f, 1.0f);
    if (ray.d.y() > 0.2f)
        return Color3f(kInfinity);
    return Color3f(1.0f);
}

/// Returns invalidRadiance(ray) (test-only plugin).
class InvalidRadianceIntegrator : public Integrator {
public:
    explicit InvalidRadianceIntegrator(const PropertyList &) {}
    Color3f Li(const Scene *, Sampler *, const Ray3f &ray) const override {
        return invalidRadiance(ray);
    }
    std::string toString() const override { return "InvalidRadianceIntegrator[]"; }
};
NORI_REGISTER_CLASS(InvalidRadianceIntegrator, "test_invalid");

std::atomic<bool> g_cancel{false};
std::atomic<int> g_calls{0};

/// Returns 1 and raises g_cancel after `calls` radiance queries (test-only plugin).
class CancellingIntegrator : public Integrator {
public:
    explicit CancellingIntegrator(const PropertyList &props) : m_calls(props.getInteger("calls")) {}
    Color3f Li(const Scene *, Sampler *, const Ray3f &) const override {
        if (++g_calls >= m_calls)
            g_cancel = true;
        return Color3f(1.0f);
    }
    std::string toString() const override { return "CancellingIntegrator[]"; }

private:
    int m_calls;
};
NORI_REGISTER_CLASS(CancellingIntegrator, "test_cancel");

/// A small AO scene; `samplerExtra` is added to the sampler's properties.
std::string spheresScene(const std::string &samplerExtra = "") {
    return R"(<scene>
    <integrator type="ao"/>
    <sampler type="independent"><integer name="sampleCount" value="4"/>)" +
           samplerExtra + R"(</sampler>
    <camera type="perspective">
        <integer name="width" value="70"/><integer name="height" value="45"/>
        <transform name="toWorld"><lookat origin="0,1,6" target="0,0.5,0"/></transform>
    </camera>
    <mesh type="sphere"><point name="center" value="0,1,0"/></mesh>
    <mesh type="sphere"><point name="center" value="1.5,0.5,0.5"/><float name="radius" value="0.5"/></mesh>
    <mesh type="sphere"><point name="center" value="0,-1000,0"/><float name="radius" value="1000"/></mesh>
</scene>)";
}

} // namespace

TEST_CASE("An image is bit-identical with one and two threads", "[render]") {
    auto scene = loadScene(spheresScene());
    RenderResult one = renderScene(*scene, quietOptions(1));
    RenderResult two = renderScene(*scene, quietOptions(2));
    REQUIRE(one.complete);
    REQUIRE(two.complete);
    CHECK(one.passes == 3); // 1, 1 and 2 samples per pixel
    CHECK(one.samplesTaken == 70u * 45u * 4u);
    bool identical = true;
    for (int y = 0; y < one.image.height(); ++y)
        for (int x = 0; x < one.image.width(); ++x)
            identical &= (one.image(y, x) == two.image(y, x)).all();
    CHECK(identical);
    // And the image is not trivially constant: AO varies across it.
    CHECK(one.image.unaryExpr([](const Color3f &c) { return c.r(); }).maxCoeff() > 0.9f);
    CHECK(one.image.unaryExpr([](const Color3f &c) { return c.r(); }).minCoeff() < 0.5f);

    // A different seed gives a different image: per-pixel seeding is not a constant.
    auto reseeded = loadScene(spheresScene(R"(<integer name="seed" value="1"/>)"));
    RenderResult other = renderScene(*reseeded, quietOptions(2));
    bool anyDifferent = false;
    for (int y = 0; y < one.image.height(); ++y)
        for (int x = 0; x < one.image.width(); ++x)
            anyDifferent |= !(one.image(y, x) == other.image(y, x)).all();
    CHECK(anyDifferent);
}

TEST_CASE("The normals integrator returns |n| of the analytic sphere", "[render][integrator]") {
    const Point3f center(0.3f, -0.2f, 0.1f);
    const float radius = 1.2f;
    auto scene = loadScene(R"(<scene>
        <integrator type="normals"/>
        <camera type="perspective"><integer name="width" value="32"/><integer name="height" value="32"/>
            <transform name="toWorld"><lookat origin="0,0,5" target="0,0,0"/></transform>
            <rfilter type="box"/></camera>
        <mesh type="sphere"><point name="center" value="0.3,-0.2,0.1"/><float name="radius" value="1.2"/></mesh>
    </scene>)");

    // The analytic first hit of a ray with the sphere, or false.
    auto analyticNormal = [&](const Ray3f &ray, Vector3f &normal) {
        const Vector3f f = ray.o - center;
        const double b = f.dot(ray.d), c = f.squaredNorm() - radius * radius;
        const double discriminant = b * b - c; // |d| = 1
        if (discriminant < 0.0)
            return false;
        const double t = -b - std::sqrt(discriminant);
        normal = (Vector3f(ray.o + static_cast<float>(t) * ray.d) - center).normalized();
        return true;
    };

    SECTION("per ray") {
        PCG32 rng(7, 11);
        std::unique_ptr<Sampler> sampler = scene->getSampler()->clone();
        int hits = 0, misses = 0;
        for (int i = 0; i < 20000; ++i) {
            Ray3f ray;
            scene->getCamera()->sampleRay(ray, Point2f(32 * rng.nextFloat(), 32 * rng.nextFloat()),
                                          Point2f(0.5f, 0.5f));
            Color3f value = scene->getIntegrator()->Li(scene.get(), sampler.get(), ray);
            Vector3f normal;
            if (analyticNormal(ray, normal)) {
                // Near the silhouette t = -b - sqrt(b² - c) is ill-conditioned, and a
                // float hit may even miss; compare only where |cos| > 0.05.
                if (std::abs(normal.dot(ray.d)) < 0.05f)
                    continue;
                ++hits;
                // float intersection vs double reference: a few ulps of the radius.
                CHECK(value.isApprox(Color3f(normal.cwiseAbs().array()), 1e-4f));
            } else {
                ++misses;
                CHECK((value == 0.0f).all());
            }
        }
        CHECK(hits > 5000);
        CHECK(misses > 5000);
    }

    SECTION("per pixel, rendered") {
        RenderResult result = renderScene(*scene, [] {
            RenderOptions options = quietOptions(2);
            options.samplesPerPixel = 256;
            return options;
        }());
        int checked = 0;
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) {
                // Expected value: |n| averaged over the pixel on a 16x16 grid, for pixels
                // entirely covered by the sphere.
                Color3f expected(0.0f);
                bool covered = true;
                for (int s = 0; s < 256 && covered; ++s) {
                    Ray3f ray;
                    scene->getCamera()->sampleRay(
                        ray, Point2f(x + (s % 16 + 0.5f) / 16, y + (s / 16 + 0.5f) / 16),
                        Point2f(0.5f, 0.5f));
                    Vector3f normal;
                    covered = analyticNormal(ray, normal);
                    expected += Color3f(normal.cwiseAbs().array()) / 256.0f;
                }
                if (!covered)
                    continue;
                ++checked;
                // 256 random samples vs the grid mean: |n| varies by < 0.1 across a pixel
                // here, so the Monte Carlo error is below 0.1/√256 ≈ 0.006.
                CHECK(((result.image(y, x) - expected).abs() < 0.01f).all());
            }
        CHECK(checked > 300);
    }
}

TEST_CASE("NaN, infinite and negative radiance is counted, not splatted", "[render]") {
    auto scene = loadScene(R"(<scene><integrator type="test_invalid"/>
        <camera type="perspective"><integer name="width" value="40"/><integer name="height" value="40"/>
            <float name="fov" value="60"/></camera></scene>)");
    RenderResult result = renderScene(*scene, quietOptions(2));
    // The expected fraction of invalid samples, from a fine grid over the film; the
    // count is binomial, so it lies within 5 standard deviations of the mean.
    int invalid = 0;
    const int grid = 400;
    for (int i = 0; i < grid * grid; ++i) {
        Ray3f ray;
        scene->getCamera()->sampleRay(
            ray, Point2f(40.0f * (i % grid + 0.5f) / grid, 40.0f * (i / grid + 0.5f) / grid),
            Point2f(0.5f, 0.5f));
        invalid += invalidRadiance(ray).isValid() ? 0 : 1;
    }
    const double p = static_cast<double>(invalid) / (grid * grid);
    const double mean = 1600.0 * p, sigma = std::sqrt(1600.0 * p * (1.0 - p));
    CHECK(p > 0.3);
    CHECK(std::abs(static_cast<double>(result.invalidSamples) - mean) < 5.0 * sigma);
    bool allFinite = true;
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 40; ++x)
            allFinite &= result.image(y, x).isValid();
    CHECK(allFinite);
    // The centre only received valid samples of value 1.
    CHECK(result.image(20, 20).isApprox(Color3f(1.0f)));
}

TEST_CASE("Cancelling keeps the finished passes: a whole frame at fewer samples", "[render]") {
    auto scene = loadScene(
        R"(<scene><integrator type="test_cancel"><integer name="calls" value="9000"/></integrator>
        <sampler type="independent"><integer name="sampleCount" value="8"/></sampler>
        <camera type="perspective"><integer name="width" value="64"/><integer name="height" value="64"/>
            <rfilter type="box"/></camera></scene>)");
    g_cancel = false;
    g_calls = 0;
    RenderOptions options = quietOptions(2);
    options.cancel = &g_cancel;
    RenderResult result = renderScene(*scene, options);
    // Passes of 1, 1, 2, 4 spp over 4096 pixels: the 9000th sample is in the third pass,
    // which is dropped; the first two remain, in every pixel.
    CHECK(result.cancelled);
    CHECK_FALSE(result.complete);
    CHECK(result.passes == 2);
    CHECK(result.samplesPerPixel == 2);
    CHECK(result.samplesTaken == 2u * 64u * 64u);
    bool allOne = true;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            allOne &= result.image(y, x).isApprox(Color3f(1.0f));
    CHECK(allOne);
}

TEST_CASE("A scene without lights renders black with every light-sampling integrator",
          "[render][integrator]") {
    // pbrt-v4 files may have no light; the light tree then has nothing to walk.
    for (const char *integrator :
         {"direct", "path", "path_mis", "volpath", "bdpt", "lighttracer"}) {
        INFO(integrator);
        const std::shared_ptr<Scene> scene = loadScene(fmt::format(R"(<scene>
            <integrator type="{}"/>
            <sampler type="independent"><integer name="sampleCount" value="2"/></sampler>
            <camera type="perspective"><integer name="width" value="8"/>
                <integer name="height" value="8"/>
                <transform name="toWorld"><lookat origin="0, 0, 4" target="0, 0, 0"/></transform>
            </camera>
            <mesh type="sphere"><bsdf type="diffuse"/></mesh>
        </scene>)",
                                                                   integrator));
        const Bitmap image = renderScene(*scene, quietOptions(2)).layers.layer("");
        CHECK((image.unaryExpr([](const Color3f &c) { return c.maxCoeff(); }) == 0.0f).all());
    }
}

TEST_CASE("sampleBorder lets edge pixels see past the image's edge through their filter",
          "[render][camera]") {
    // A black square fills the image exactly (fov 90° at distance 1), a white sky lies
    // beyond it: the filter cut at the edge sees only black, the whole filter (pbrt-v4's
    // film) reaches the sky from the edge pixels, and not from the middle ones.
    for (const bool border : {false, true}) {
        INFO("sampleBorder " << border);
        const std::shared_ptr<Scene> scene = loadScene(fmt::format(R"(<scene>
            <integrator type="path"/>
            <sampler type="independent"><integer name="sampleCount" value="64"/></sampler>
            <camera type="perspective"><integer name="width" value="8"/>
                <integer name="height" value="8"/> <float name="fov" value="90"/>
                <boolean name="sampleBorder" value="{}"/>
                <transform name="toWorld"><lookat origin="0, 0, 0" target="0, 0, 1"/></transform>
                <rfilter type="gaussian"/>
            </camera>
            <emitter type="constant"><color name="radiance" value="1"/></emitter>
            <mesh type="rectangle"><bsdf type="diffuse"><color name="albedo" value="0"/></bsdf>
                <transform name="toWorld"><translate value="0, 0, 1"/></transform></mesh>
        </scene>)",
                                                                   border));
        const Bitmap image = renderScene(*scene, quietOptions(2)).layers.layer("");
        CHECK(image(3, 3).maxCoeff() == 0.0f);
        if (border)
            CHECK(image(0, 3).minCoeff() > 0.02f);
        else
            CHECK(image(0, 3).maxCoeff() == 0.0f);
    }
}
