// Light tracing (plugins/builtin/integrators/lighttracer.cpp) and what it stands on: connections
// to the camera (Camera::connect), the film's splats (SplatBuffer), and renders with
// splats that stay deterministic, split into parts, and refuse what they cannot do.
#include "app/renderpart.h"
#include "testutil.h"
#include <nori/camera.h>
#include <nori/parser.h>
#include <nori/splatbuffer.h>
#include <nori/statistics.h>

#include <catch2/catch.hpp>

#include <cmath>

using namespace nori;
using namespace nori::testing;

namespace {

std::shared_ptr<Camera> makeCamera(const std::string &parameters) {
    return std::dynamic_pointer_cast<Camera>(loadFromXMLString(
        fmt::format(R"(<camera type="perspective"><integer name="width" value="64"/>
            <integer name="height" value="48"/><float name="fov" value="50"/>
            <transform name="toWorld"><lookat origin="0.3, 1, 4" target="0, 0.2, 0" up="0, 1, 0"/>
            </transform>{}</camera>)",
                    parameters),
        "."));
}

/// The README's Cornell box with a diffuse sphere, rendered by the light tracer.
std::shared_ptr<Scene> lightTracedBox(int size, size_t spp) {
    LoadOptions options({{"integrator", "lighttracer"},
                         {"sphere", "diffuse"},
                         {"size", std::to_string(size)},
                         {"spp", std::to_string(spp)}});
    return std::dynamic_pointer_cast<Scene>(
        loadFromXML(std::string(NORI_SOURCE_DIR) + "/scenes/cbox/cbox.xml", options));
}

} // namespace

TEST_CASE("A connection to the camera finds the film position its camera ray came from",
          "[lighttracer][camera]") {
    for (const std::string &parameters :
         {std::string(), std::string(R"(<string name="convention" value="eth"/>)"),
          std::string(R"(<float name="apertureRadius" value="0.2"/>
                         <float name="focalDistance" value="3"/>)")}) {
        INFO("camera parameters: " << parameters);
        const std::shared_ptr<Camera> camera = makeCamera(parameters);
        REQUIRE(camera->canConnect());
        PCG32 random(7, 3);
        for (int i = 0; i < 1000; ++i) {
            const Point2f film(64.0f * random.nextFloat(), 48.0f * random.nextFloat());
            const Point2f lens(random.nextFloat(), random.nextFloat());
            Ray3f ray;
            camera->sampleRay(ray, film, lens);
            const float distance = 0.5f + 5.0f * random.nextFloat();
            CameraConnection connection;
            REQUIRE(camera->connect(ray(distance), lens, connection));
            CHECK((connection.filmPosition - film).norm() < 2e-3f);
            CHECK((connection.lensPoint - ray.o).norm() < 1e-4f);
            CHECK(connection.direction.dot(-ray.d) > 1.0f - 1e-5f);
            CHECK(std::abs(connection.distance - distance) < 1e-4f * distance);
        }
        // Behind the camera, and outside the field of view, nothing is seen.
        Ray3f centre;
        camera->sampleRay(centre, Point2f(32.0f, 24.0f), Point2f(0.5f, 0.5f));
        CameraConnection connection;
        CHECK_FALSE(camera->connect(centre(-1.0f), Point2f(0.5f, 0.5f), connection));
        const Vector3f sideways = centre.d.cross(Vector3f(0.0f, 1.0f, 0.0f)).normalized();
        CHECK_FALSE(
            camera->connect(centre(2.0f) + 5.0f * sideways, Point2f(0.5f, 0.5f), connection));
    }
}

TEST_CASE("The camera's importance integrates to one over the image", "[lighttracer][camera]") {
    // Over the directions from the lens, ∫ importance·d² dω = ∫ dω/(A cos³θ) over the
    // field of view = 1 (dω = cos³θ dA on the film plane at distance 1, of area A): each
    // pixel's share is 1/N, so a splat of radiance L over N·spp paths averages to L. A
    // t-test (significance 0.01, fixed seed) of a uniform-sphere estimate against 1; the
    // control drops the 1/cos³θ (planted_importance's bug) and must be rejected.
    // Also for a crop of the image and an off-centre screen window with pixels that are
    // not square (A is then the crop's share of the window).
    for (const std::string &parameters :
         {std::string(), std::string(R"(<float name="apertureRadius" value="0.2"/>)"),
          std::string(
              R"(<integer name="cropOffsetX" value="10"/><integer name="cropOffsetY" value="5"/>
              <integer name="cropWidth" value="40"/><integer name="cropHeight" value="30"/>)"),
          std::string(R"(<string name="screenWindow" value="-0.4 1.2 -0.9 0.3"/>
              <integer name="cropOffsetX" value="3"/><integer name="cropWidth" value="50"/>
              <float name="apertureRadius" value="0.2"/>)")}) {
        INFO("camera parameters: " << parameters);
        const std::shared_ptr<Camera> camera = makeCamera(parameters);
        Ray3f axis;
        camera->sampleRay(axis, Point2f(32.0f, 24.0f), Point2f(0.5f, 0.5f));
        PCG32 random(11, 5);
        RunningMoments estimate, control;
        constexpr int kSamples = 200000;
        for (int i = 0; i < kSamples; ++i) {
            const Point2f lens(random.nextFloat(), random.nextFloat());
            // The lens point itself, from the connection of a point in front of it.
            CameraConnection probe;
            REQUIRE(camera->connect(axis(3.0f), lens, probe));
            const Vector3f direction = randomDirection(random);
            const float pdf = 1.0f / (4.0f * kPi);
            CameraConnection connection;
            double value = 0.0, controlValue = 0.0;
            if (camera->connect(probe.lensPoint + 2.0f * direction, lens, connection)) {
                value = connection.importance * connection.distance * connection.distance / pdf;
                const float cosTheta = direction.dot(axis.d);
                controlValue = value * cosTheta * cosTheta * cosTheta;
            }
            estimate.add(value);
            control.add(controlValue);
        }
        const StudentTResult result =
            studentTTest(estimate.mean, estimate.variance(), estimate.count, 1.0, 0.01);
        const StudentTResult rejected =
            studentTTest(control.mean, control.variance(), control.count, 1.0, 0.01);
        INFO("importance: mean " << estimate.mean << ", t = " << result.t
                                 << "; without 1/cos³: " << control.mean << ", t = " << rejected.t);
        CHECK(result.passed);
        CHECK_FALSE(rejected.passed);
    }
}

TEST_CASE("Splats are divided by the filter's integral over the image, edges included",
          "[lighttracer][film]") {
    // Splats on a regular grid 1/64 of a pixel apart, each carrying its cell's area, make
    // a constant image of 1: ∫ f(x − c)/F dx over the image. The grid's cells each lie
    // within one step of the filter's table (radius/32 from the pixel centre, a multiple
    // of 1/64 for these radii), so the sum is the integral up to float rounding; at the
    // edges the filter is cut and F with it (without the division an edge pixel of the
    // gaussian would read 0.5). The sums are in float: a pixel adds n = (64·2r)² terms,
    // which any order rounds by at most n·2⁻²⁴ of their sum (Higham, "Accuracy and
    // Stability of Numerical Algorithms", §4.2).
    const Vector2i size(6, 5);
    for (const std::string &filterXML :
         {std::string(R"(<rfilter type="box"/>)"), std::string(R"(<rfilter type="gaussian"/>)"),
          std::string(R"(<rfilter type="tent"><float name="radius" value="1.5"/></rfilter>)"),
          std::string(R"(<rfilter type="mitchell"/>)")}) {
        INFO(filterXML);
        const auto filter =
            std::dynamic_pointer_cast<ReconstructionFilter>(loadFromXMLString(filterXML, "."));
        SplatBuffer buffer(size, filter.get(), true);
        constexpr int kPerPixel = 64;
        const float cell = 1.0f / kPerPixel;
        // Two lists of the whole grid at half the value: the even samples' and the odd's.
        std::vector<std::vector<SplatBuffer::Record>> lists(2);
        for (size_t list = 0; list < lists.size(); ++list)
            for (int y = 0; y < size.y() * kPerPixel; ++y)
                for (int x = 0; x < size.x() * kPerPixel; ++x)
                    lists[list].push_back({Point2f((static_cast<float>(x) + 0.5f) * cell,
                                                   (static_cast<float>(y) + 0.5f) * cell),
                                           Color3f(0.5f * cell * cell), list == 0});
        buffer.add(lists);
        const double terms = 2.0 * std::pow(2.0 * kPerPixel * filter->getRadius(), 2.0);
        const double rounding = terms * std::ldexp(1.0, -24);
        for (int y = 0; y < size.y(); ++y)
            for (int x = 0; x < size.x(); ++x) {
                INFO("pixel " << x << ", " << y);
                CHECK(std::abs(buffer.sum(x, y).r() - 1.0) <= rounding);
                CHECK(std::abs(buffer.evenSum(x, y).r() - 0.5) <= rounding);
            }
    }
}

TEST_CASE("A light-traced image is the same for any thread count", "[lighttracer][render]") {
    // 96² pixels and 64 spp: passes of at most 2^19 samples, so several passes whose
    // splats are merged block by block in a fixed order.
    const std::shared_ptr<Scene> scene = lightTracedBox(96, 64);
    RenderOptions options = quietOptions(1);
    options.aovs = {AOV::Variance};
    const RenderResult one = renderScene(*scene, options);
    options.threads = 2;
    const RenderResult two = renderScene(*scene, options);
    CHECK(one.passes > 2);
    CHECK(identicalImages(one.image, two.image));
    CHECK((one.layers.channels().at("variance.G") == two.layers.channels().at("variance.G")).all());
    CHECK(one.layers.channels().at("G").maxCoeff() > 0.0f);
}

TEST_CASE("A light-traced render split in parts merges to the single render",
          "[lighttracer][parts]") {
    const std::shared_ptr<Scene> scene = lightTracedBox(40, 16);
    RenderOptions options = quietOptions(2);
    const RenderResult single = renderScene(*scene, options);
    TempDir dir;
    std::vector<std::string> files;
    for (int k = 1; k <= 4; ++k) {
        const RenderResult part = renderPart(*scene, options, {k, 4}, "0123456789abcdef", "cbox");
        files.push_back((dir.path() / fmt::format("part{}.exr", k)).string());
        part.layers.saveEXR(files.back());
    }
    // The same sums in another order: equal up to float rounding, which stays far below
    // a thousandth of the brightest pixel; a part left out changes pixels by about a
    // quarter of their value.
    const auto worstDifference = [&](const LayeredImage &merged) {
        const LayeredImage::Channel &a = merged.channels().at("G");
        const LayeredImage::Channel &b = single.layers.channels().at("G");
        return (a - b).abs().maxCoeff() / b.maxCoeff();
    };
    CHECK(worstDifference(mergeParts(files, false).image) < 1e-4);
    CHECK(worstDifference(mergeParts({files[0], files[1], files[2]}, true).image) > 1e-2);
}

TEST_CASE("The light tracer says what it cannot render", "[lighttracer]") {
    const std::string box = R"(<integrator type="lighttracer"/>
        <sampler type="independent"><integer name="sampleCount" value="1"/>{}</sampler>
        <mesh type="sphere"><float name="radius" value="1"/>{}
            <emitter type="area"><color name="radiance" value="1"/></emitter></mesh>{})";
    const std::string camera = R"(<camera type="perspective"><integer name="width" value="4"/>
        <integer name="height" value="4"/><transform name="toWorld">
        <lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform></camera>)";
    const auto render = [](const std::string &body) {
        std::shared_ptr<Scene> scene = loadScene("<scene>" + body + "</scene>");
        renderScene(*scene, quietOptions(1));
    };
    CHECK_THAT(errorOf([&] { render(fmt::format(box, "", "", camera)); }), Catch::Equals(""));
    CHECK_THAT(errorOf([&] {
                   render(
                       fmt::format(box, R"(<float name="maxTolerance" value="0.1"/>)", "", camera));
               }),
               Catch::Contains("adaptive sampling") && Catch::Contains("lighttracer"));
    CHECK_THAT(
        errorOf([&] {
            render(fmt::format(box, "", R"(<medium type="homogeneous" name="interior"/>)", camera));
        }),
        Catch::Contains("lighttracer") && Catch::Contains("participating media"));
}
