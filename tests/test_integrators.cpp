// The first integrators against analytic answers: the point-light `simple` integrator
// (inverse-square law) and ambient occlusion under a sphere.
#include <nori/parser.h>
#include <nori/sampler.h>
#include <nori/scene.h>

#include "testutil.h"

#include <catch2/catch.hpp>

using namespace nori;
using nori::testing::TempDir;

namespace {

const char *kFloorObj = "v -10 0 -10\nv -10 0 10\nv 10 0 10\nv 10 0 -10\nf 1 2 3 4\n";

std::shared_ptr<Scene> sceneWithFloor(const TempDir &dir, const std::string &content) {
    dir.write("floor.obj", kFloorObj);
    auto scene = std::dynamic_pointer_cast<Scene>(loadFromXMLString(
        "<scene><camera type=\"perspective\"/>"
        "<mesh type=\"obj\"><string name=\"filename\" value=\"floor.obj\"/></mesh>" +
            content + "</scene>",
        dir.path().string()));
    REQUIRE(scene);
    return scene;
}

} // namespace

TEST_CASE("simple: a point light over a plane follows the inverse-square law", "[integrator]") {
    TempDir dir;
    // Φ = 4π² makes L = cos θ / d² (the integrator computes Φ/(4π²) · cos θ / d²).
    auto scene = sceneWithFloor(dir, R"(
        <integrator type="simple">
            <point name="position" value="0, 2, 0"/>
            <color name="energy" value="39.4784176, 39.4784176, 39.4784176"/>
        </integrator>
        <mesh type="sphere"><point name="center" value="3, 1, 0"/><float name="radius" value="0.5"/></mesh>)");
    std::unique_ptr<Sampler> sampler = scene->getSampler()->clone();
    const Point3f light(0, 2, 0), eye(0, 6, 6);
    for (const Point3f &target :
         {Point3f(0, 0, 0), Point3f(1, 0, 1), Point3f(-2, 0, 0.5f), Point3f(0, 0, -3)}) {
        Ray3f ray(eye, (target - eye).normalized());
        const Vector3f toLight = light - target;
        const float d = toLight.norm();
        const float expected = (toLight.y() / d) / (d * d);
        Color3f value = scene->getIntegrator()->Li(scene.get(), sampler.get(), ray);
        INFO("target " << target.transpose());
        CHECK(value.r() == Approx(expected).epsilon(1e-4));
    }
    // Behind the sphere (on the line from the light through its centre) it is dark.
    const Point3f shadowed = light + 2.0f * (Point3f(3, 1, 0) - light);
    Color3f dark = scene->getIntegrator()->Li(scene.get(), sampler.get(),
                                              Ray3f(eye, (shadowed - eye).normalized()));
    CHECK(dark.r() == 0.0f);
}

TEST_CASE("ao: occlusion by a sphere above a plane is 1 - sin²α", "[integrator]") {
    TempDir dir;
    // A sphere of radius r centred at height h above the origin subtends a cone of
    // half-angle α, sin α = r/h, around the normal; its cosine-weighted solid angle
    // fraction is sin²α, so AO = 1 - (r/h)² = 0.75 here.
    const std::string sphere =
        R"(<mesh type="sphere"><point name="center" value="0, 2, 0"/><float name="radius" value="1"/></mesh>)";
    auto scene = sceneWithFloor(dir, "<integrator type=\"ao\"/>" + sphere);
    auto shortRange = sceneWithFloor(
        dir,
        "<integrator type=\"ao\"><float name=\"length\" value=\"0.5\"/></integrator>" + sphere);

    // A grazing camera ray that hits the floor at the origin, passing under the sphere.
    const Ray3f ray(Point3f(5, 0.5f, 0), Vector3f(-5, -0.5f, 0).normalized());
    std::unique_ptr<Sampler> sampler = scene->getSampler()->clone();
    const int n = 20000;
    double sum = 0.0, sumShort = 0.0;
    for (int i = 0; i < n; ++i) {
        sampler->generate(Point2i(i, 0));
        sum += scene->getIntegrator()->Li(scene.get(), sampler.get(), ray).r();
        sumShort += shortRange->getIntegrator()->Li(shortRange.get(), sampler.get(), ray).r();
    }
    const double expected = 0.75;
    // Visibility is Bernoulli: σ = √(p(1-p)/n) ≈ 0.0031; allow 5σ.
    const double tolerance = 5.0 * std::sqrt(expected * (1.0 - expected) / n);
    CHECK(std::abs(sum / n - expected) < tolerance);
    // The test has the power to see a wrong sampler: uniform hemisphere directions would
    // give 1 − (1 − cos α) = cos α ≈ 0.866, more than 25σ away.
    CHECK(std::abs(std::cos(std::asin(0.5)) - expected) > 5.0 * tolerance);
    // With length 0.5 the sphere (at distance ≥ 1) no longer occludes.
    CHECK(sumShort / n == 1.0);
}
