// Cameras: the two course conventions for the image's x axis, chosen in the scene or on
// the command line.
#include <nori/bitmap.h>
#include <nori/camera.h>
#include <nori/parser.h>
#include <nori/pcg32.h>
#include <nori/scene.h>
#include <nori/spectrum.h>

#include "testutil.h"

#include <catch2/catch.hpp>

using namespace nori;
using Catch::Contains;
using nori::testing::distanceToRay;
using nori::testing::errorOf;
using nori::testing::runNori;
using nori::testing::TempDir;

namespace {

/// A camera at (0, 0, 5) looking at the origin: camera-space +x is world −x.
std::string cameraScene(const std::string &convention) {
    return R"(<scene><integrator type="normals"/>
        <camera type="perspective"><integer name="width" value="40"/><integer name="height" value="20"/>
            <transform name="toWorld"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>)" +
           convention + "</camera></scene>";
}

/// The world-space x direction of the ray through the left edge of the image's middle row.
float leftEdgeRayX(const Scene &scene) {
    Ray3f ray;
    scene.getCamera()->sampleRay(ray, Point2f(0.0f, 10.0f), Point2f(0.5f, 0.5f));
    return ray.d.x();
}

std::shared_ptr<Scene> load(const std::string &xml, const LoadOptions &options = {}) {
    auto scene = std::dynamic_pointer_cast<Scene>(loadFromXMLString(xml, ".", options));
    REQUIRE(scene);
    return scene;
}

} // namespace

TEST_CASE("EPFL's convention mirrors x, ETH's does not", "[camera]") {
    // EPFL (Nori 2): camera +x is the image's left, so the left edge looks toward
    // camera +x, which is world −x here.
    CHECK(leftEdgeRayX(*load(cameraScene(""))) < -0.1f);
    CHECK(leftEdgeRayX(*load(cameraScene(R"(<string name="convention" value="epfl"/>)"))) < -0.1f);
    // ETH: the image's left is camera −x = world +x.
    CHECK(leftEdgeRayX(*load(cameraScene(R"(<string name="convention" value="eth"/>)"))) > 0.1f);
    // The two are exact mirrors of each other.
    Ray3f epfl, eth;
    load(cameraScene(""))->getCamera()->sampleRay(epfl, Point2f(7.25f, 3.5f), Point2f(0.5f, 0.5f));
    load(cameraScene(R"(<string name="convention" value="eth"/>)"))
        ->getCamera()
        ->sampleRay(eth, Point2f(40.0f - 7.25f, 3.5f), Point2f(0.5f, 0.5f));
    CHECK(epfl.d.isApprox(eth.d, 1e-6f));
    CHECK(epfl.o.isApprox(eth.o));

    CHECK_THAT(errorOf([] { load(cameraScene(R"(<string name="convention" value="mit"/>)")); }),
               Contains("'convention' must be \"epfl\"") && Contains("got 'mit'"));
}

TEST_CASE("The command line's camera convention applies to cameras that do not choose one",
          "[camera][cli]") {
    LoadOptions ethOptions;
    ethOptions.convention = "eth";
    CHECK(leftEdgeRayX(*load(cameraScene(""), ethOptions)) > 0.1f);
    // A convention written in the scene wins.
    CHECK(leftEdgeRayX(*load(cameraScene(R"(<string name="convention" value="epfl"/>)"),
                             ethOptions)) < -0.1f);

    // Through the program: an ETH render is the mirror image of the EPFL one. A sphere
    // at world x = −1.5 is on camera +x: the image's left for EPFL, right for ETH.
    TempDir dir;
    const std::string scene = dir.write("scene.xml", R"(<scene><integrator type="normals"/>
        <camera type="perspective"><integer name="width" value="40"/><integer name="height" value="20"/>
            <float name="fov" value="60"/>
            <transform name="toWorld"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
        </camera>
        <mesh type="sphere"><point name="center" value="-1.5,0,0"/><float name="radius" value="0.5"/></mesh>
    </scene>)");
    auto litColumns = [&](const std::vector<std::string> &extra) {
        std::vector<std::string> arguments = extra;
        // 16 spp: a pixel the sphere's silhouette crosses is lit in both renders.
        arguments.insert(arguments.end(), {"--no-progress", "--spp", "16", "-o",
                                           (dir.path() / "out").string(), scene});
        auto result = runNori(arguments);
        INFO(result.output);
        REQUIRE(result.exitCode == 0);
        const Bitmap image = Bitmap::load((dir.path() / "out.exr").string());
        int left = 0, right = 0;
        for (int x = 0; x < image.width(); ++x)
            if (image(10, x).maxCoeff() > 0.0f)
                (x < image.width() / 2 ? left : right)++;
        return std::make_pair(left, right);
    };
    const auto epfl = litColumns({});
    CHECK(epfl.first > 3);
    CHECK(epfl.second == 0);
    const auto eth = litColumns({"--camera-convention", "eth"});
    CHECK(eth.first == 0);
    // Silhouette pixels are lit or not by random samples inside them: one column apart.
    CHECK(std::abs(eth.second - epfl.first) <= 1);

    auto bad = runNori({"--camera-convention", "left", scene});
    CHECK(bad.exitCode == 1);
    CHECK_THAT(bad.output, Contains("--convention must be 'epfl' or 'eth'"));
}

TEST_CASE("A camera's lookat with 'up' along the view collapses as in Nori 2, and warns",
          "[camera]") {
    // ETH's test-sphere.xml looks straight down with up = +z; its references are the values
    // of the one ray Nori 2's collapsed camera casts from every pixel.
    TempDir dir;
    const std::string scene = dir.write("down.xml", R"(<scene><integrator type="normals"/>
        <camera type="perspective"><integer name="width" value="8"/><integer name="height" value="6"/>
            <transform name="toWorld"><lookat origin="0.3,0.2,5" target="0.3,0.2,0" up="0,0,1"/></transform>
        </camera>
        <mesh type="sphere"><point name="center" value="0.3,0.2,0"/></mesh></scene>)");
    const auto loaded = std::dynamic_pointer_cast<Scene>(loadFromXML(scene));
    REQUIRE(loaded);
    for (const Point2f &pixel : {Point2f(0.1f, 0.2f), Point2f(4.0f, 3.0f), Point2f(7.9f, 5.9f)}) {
        Ray3f ray;
        loaded->getCamera()->sampleRay(ray, pixel, Point2f(0.5f, 0.5f));
        CHECK(ray.o.isApprox(Point3f(0.3f, 0.2f, 5.0f)));
        CHECK(ray.d.isApprox(Vector3f(0.0f, 0.0f, -1.0f)));
        // The clip distances stay distances from the eye, as for any camera.
        CHECK(ray.mint == Approx(1e-4f).epsilon(1e-4));
    }

    const std::string output = dir.path().string() + "/down.exr";
    const auto run = runNori({"--no-progress", "--spp", "4", "-o", output, scene});
    REQUIRE(run.exitCode == 0);
    CHECK_THAT(run.output, Contains("down.xml:3:40") && Contains("Warning:") &&
                               Contains("parallel to the viewing direction"));
    const Bitmap image = Bitmap::load(output);
    for (Eigen::Index y = 0; y < image.rows(); ++y)
        for (Eigen::Index x = 0; x < image.cols(); ++x)
            CHECK(image(y, x).isApprox(Color3f(0.0f, 0.0f, 1.0f)));
}

TEST_CASE("lookat with 'up' along the view outside a camera is a located error", "[camera]") {
    const std::string xml = R"(<scene><integrator type="normals"/><camera type="perspective"/>
        <emitter type="spot">
            <transform name="toWorld"><lookat origin="0,0,5" target="0,0,0" up="0,0,1"/></transform>
        </emitter></scene>)";
    CHECK_THAT(errorOf([&] { load(xml); }),
               Contains("<string>:3:40") &&
                   Contains("'up' is zero or parallel to the viewing direction"));
}

namespace {

std::shared_ptr<Camera> makeCamera(const std::string &type, const std::string &parameters) {
    auto camera = std::dynamic_pointer_cast<Camera>(loadFromXMLString(fmt::format(
        R"(<camera type="{}"><integer name="width" value="64"/><integer name="height" value="48"/>
            <float name="fov" value="40"/>
            <transform name="toWorld"><lookat origin="1, 2, 6" target="0, 0, 0" up="0, 1, 0"/></transform>
            {}</camera>)",
        type, parameters)));
    REQUIRE(camera);
    return camera;
}

} // namespace

TEST_CASE("A thin lens of aperture 0 is the pinhole camera, bit for bit", "[camera][thinlens]") {
    auto pinhole = makeCamera("perspective", "");
    auto thin = makeCamera("thinlens", R"(<float name="apertureRadius" value="0"/>
        <float name="focalDistance" value="3"/>)");
    PCG32 random(1, 2);
    for (int i = 0; i < 1000; ++i) {
        const Point2f film(64.0f * random.nextFloat(), 48.0f * random.nextFloat());
        const Point2f aperture(random.nextFloat(), random.nextFloat());
        Ray3f a, b;
        pinhole->sampleRay(a, film, aperture);
        thin->sampleRay(b, film, aperture);
        REQUIRE(a.o == b.o);
        REQUIRE(a.d == b.d);
        REQUIRE(a.mint == b.mint);
        REQUIRE(a.maxt == b.maxt);
    }
}

TEST_CASE("A thin lens images a point of its focal plane to one pixel at any aperture",
          "[camera][thinlens]") {
    const float focalDistance = 4.0f;
    auto pinhole = makeCamera("perspective", "");
    for (float aperture : {0.01f, 0.1f, 0.5f}) {
        CAPTURE(aperture);
        auto thin = makeCamera("thinlens", fmt::format(R"(<float name="apertureRadius" value="{}"/>
            <float name="focalDistance" value="{}"/>)",
                                                       aperture, focalDistance));
        PCG32 random(3, 4);
        for (const Point2f &film : {Point2f(32.0f, 24.0f), Point2f(5.5f, 40.25f)}) {
            // The point of the focal plane (at focalDistance along the view axis) that the
            // pinhole ray through this film position reaches.
            Ray3f center;
            pinhole->sampleRay(center, film, Point2f(0.5f, 0.5f));
            const Vector3f axis = Vector3f(Point3f(0, 0, 0) - Point3f(1, 2, 6)).normalized();
            const Point3f focus = center.o + center.d * (focalDistance / center.d.dot(axis));
            // Every lens sample's ray passes through it; a point off the plane is blurred.
            const Point3f offPlane =
                center.o + center.d * (2.0f * focalDistance / center.d.dot(axis));
            float spread = 0.0f;
            for (int i = 0; i < 200; ++i) {
                Ray3f ray;
                thin->sampleRay(ray, film, Point2f(random.nextFloat(), random.nextFloat()));
                CHECK(distanceToRay(focus, ray) < 1e-4f * focalDistance);
                spread = std::max(spread, distanceToRay(offPlane, ray));
            }
            CHECK(spread > 0.5f * aperture); // the control: out of focus, rays miss by ~aperture
        }
    }
}

TEST_CASE("Thin-lens parameters are checked", "[camera][thinlens]") {
    CHECK_THAT(
        errorOf([] { makeCamera("thinlens", R"(<float name="apertureRadius" value="-1"/>)"); }),
        Contains("'apertureRadius' must be finite and not negative, got -1"));
    CHECK_THAT(
        errorOf([] { makeCamera("thinlens", R"(<float name="focalDistance" value="0"/>)"); }),
        Contains("'focalDistance' must be positive, got 0"));
}

TEST_CASE("A crop renders the full image's pixels: rays, connections and densities",
          "[camera][crop]") {
    const std::string crop = R"(<integer name="cropOffsetX" value="10"/>
        <integer name="cropOffsetY" value="7"/><integer name="cropWidth" value="30"/>
        <integer name="cropHeight" value="20"/>)";
    for (const std::string &lens :
         {std::string(), std::string(R"(<float name="apertureRadius" value="0.2"/>
              <float name="focalDistance" value="5"/>)")}) {
        CAPTURE(lens);
        auto full = makeCamera("perspective", lens);
        auto cropped = makeCamera("perspective", lens + crop);
        CHECK(cropped->getOutputSize() == Vector2i(30, 20));
        CHECK(cropped->getFullSize() == Vector2i(64, 48));
        PCG32 random(5, 6);
        for (int i = 0; i < 500; ++i) {
            const Point2f film(30.0f * random.nextFloat(), 20.0f * random.nextFloat());
            const Point2f aperture(random.nextFloat(), random.nextFloat());
            Ray3f a, b;
            cropped->sampleRay(a, film, aperture);
            full->sampleRay(b, Point2f(film + Point2f(10.0f, 7.0f)), aperture);
            REQUIRE(a.o.isApprox(b.o, 1e-6f));
            REQUIRE(a.d.isApprox(b.d, 1e-6f));
            // The connection back to the film lands on the crop's own pixel, and the
            // density is the full image's times its share of the film (1/A of a smaller A).
            CameraConnection connection;
            const Point3f target = b.o + 3.0f * b.d;
            REQUIRE(cropped->connect(target, aperture, connection));
            CHECK((connection.filmPosition - film).norm() < 1e-3f);
            CameraConnection fullConnection;
            REQUIRE(full->connect(target, aperture, fullConnection));
            CHECK(connection.importance ==
                  Approx(fullConnection.importance * (64.0 * 48.0) / (30.0 * 20.0)).epsilon(1e-5));
            CHECK(
                cropped->pdfDirection(b.o, b.d) ==
                Approx(full->pdfDirection(b.o, b.d) * (64.0 * 48.0) / (30.0 * 20.0)).epsilon(1e-5));
        }
        // A point the full image sees outside the crop is not on the cropped film.
        Ray3f corner;
        full->sampleRay(corner, Point2f(2.0f, 2.0f), Point2f(0.5f, 0.5f));
        CameraConnection outside;
        CHECK(full->connect(corner.o + 3.0f * corner.d, Point2f(0.5f, 0.5f), outside));
        CHECK_FALSE(cropped->connect(corner.o + 3.0f * corner.d, Point2f(0.5f, 0.5f), outside));
    }
    CHECK_THAT(errorOf([] {
                   makeCamera("perspective", R"(<integer name="cropOffsetX" value="40"/>
                       <integer name="cropWidth" value="30"/>)");
               }),
               Contains("the crop of 30 x 48 pixels at (40, 0) does not lie in the image of "
                        "64 x 48 pixels"));
}

TEST_CASE("A screen window places the film on the plane at distance 1", "[camera][crop]") {
    // ETH's convention (x not mirrored): the window's corners, in units of tan(fov/2) with
    // x toward the image's right and y up, are where the image's corners look.
    auto camera = std::dynamic_pointer_cast<Camera>(loadFromXMLString(
        R"(<camera type="perspective"><integer name="width" value="64"/>
            <integer name="height" value="48"/><float name="fov" value="40"/>
            <string name="convention" value="eth"/>
            <string name="screenWindow" value="-0.5 1.5 -0.2 1"/></camera>)"));
    REQUIRE(camera);
    const float t = std::tan(degToRad(20.0f));
    auto direction = [&](float x, float y) {
        Ray3f ray;
        camera->sampleRay(ray, Point2f(x, y), Point2f(0.5f, 0.5f));
        return Vector3f(ray.d / ray.d.z());
    };
    CHECK(direction(0.0f, 0.0f).isApprox(Vector3f(-0.5f * t, 1.0f * t, 1.0f), 1e-5f));
    CHECK(direction(64.0f, 48.0f).isApprox(Vector3f(1.5f * t, -0.2f * t, 1.0f), 1e-5f));
    // The default window spans the fov on the width, the height in proportion.
    auto centred = makeCamera("perspective", R"(<string name="convention" value="eth"/>
        <string name="screenWindow" value="-1 1 -0.75 0.75"/>)");
    auto byDefault = makeCamera("perspective", R"(<string name="convention" value="eth"/>)");
    Ray3f a, b;
    centred->sampleRay(a, Point2f(3.5f, 40.25f), Point2f(0.5f, 0.5f));
    byDefault->sampleRay(b, Point2f(3.5f, 40.25f), Point2f(0.5f, 0.5f));
    CHECK(a.d.isApprox(b.d, 1e-6f));
    CHECK_THAT(errorOf([] {
                   makeCamera("perspective", R"(<string name="screenWindow" value="1 -1 0 1"/>)");
               }),
               Contains("'screenWindow' must be four finite numbers"));
}

TEST_CASE("White balance maps the illuminant's white to white, and nothing else changes",
          "[camera][spectrum]") {
    for (float temperature : {2500.0f, 3200.0f, 5000.0f, 9000.0f}) {
        CAPTURE(temperature);
        const Eigen::Matrix3f balance = whiteBalanceMatrix(temperature);
        // The white of the daylight (or blackbody) illuminant, as linear sRGB of luminance 1.
        const Eigen::Vector2d xy = daylightChromaticity(temperature);
        const Color3f white =
            xyzToLinearSRGB(xy.x() / xy.y(), 1.0, (1.0 - xy.x() - xy.y()) / xy.y());
        const Eigen::Vector3f balanced = balance * white.matrix();
        CHECK(balanced.isApprox(Eigen::Vector3f::Ones(), 1e-4f));
    }
    // D65 itself (6504 K) is balanced to itself: pbrt-v4's D(6500) is nearly no change.
    CHECK(whiteBalanceMatrix(6500.0f).isApprox(Eigen::Matrix3f::Identity(), 2e-3f));
    // A camera with a white balance passes samples through the matrix.
    auto camera = makeCamera("perspective", R"(<float name="whiteBalance" value="3200"/>)");
    REQUIRE(camera->balancesWhite());
    const Color3f sample(0.2f, 0.5f, 0.9f);
    CHECK(camera->sensorResponse(sample).matrix().isApprox(
        whiteBalanceMatrix(3200.0f) * sample.matrix(), 1e-6f));
    CHECK_FALSE(makeCamera("perspective", "")->balancesWhite());
    CHECK_THAT(errorOf([] { whiteBalanceMatrix(-5.0f); }),
               Contains("the temperature must be positive, got -5 K"));
}
