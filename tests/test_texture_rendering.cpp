// Textures in renders: the footprint that ray differentials give a hit, a normal map
// against the geometry it imitates, MIP mapping on a grazing floor, and a textured
// roughness under the χ² test. Each with a control that must fail.
#include "testutil.h"

#include <nori/bsdf.h>
#include <nori/camera.h>
#include <nori/chisquare.h>
#include <nori/integrator.h>
#include <nori/parser.h>
#include <nori/raydifferential.h>
#include <nori/render.h>
#include <nori/sampler.h>
#include <nori/samplingroutines.h>
#include <nori/scene.h>
#include <nori/statistics.h>

#include <catch2/catch.hpp>

#include <iostream>

using namespace nori;
using namespace nori::testing;

namespace {

const std::string kSceneDirectory = std::string(NORI_SOURCE_DIR) + "/scenes/textured";

/// A square perspective camera on the +z axis at `distance`, looking at the origin.
std::string cameraOnZAxis(float fov, int size, float distance) {
    return fmt::format(R"(<camera type="perspective"><float name="fov" value="{}"/>
            <integer name="width" value="{}"/> <integer name="height" value="{}"/>
            <transform name="toWorld"><lookat origin="0, 0, {}" target="0, 0, 0" up="0, 1, 0"/></transform>
        </camera>)",
                       fov, size, size, distance);
}

} // namespace

TEST_CASE("A plane seen head-on at distance d has du/dx = 2 d tan(fov/2) / (width · size)",
          "[texture][differentials]") {
    const float d = 5.0f, fov = 40.0f, scale = 3.0f;
    const int width = 64;
    auto scene = loadScene(fmt::format(R"(<scene> <integrator type="normals"/> {}
        <mesh type="obj"><string name="filename" value="meshes/floor.obj"/>
            <transform name="toWorld"><rotate axis="1, 0, 0" angle="90"/><scale value="{}"/></transform>
        </mesh></scene>)",
                                       cameraOnZAxis(fov, width, d), scale),
                           kSceneDirectory);
    // The plane spans 2·scale and its uv span [0, 1]: one pixel covers this much of u.
    const float expected = 2.0f * d * std::tan(degToRad(fov / 2.0f)) / (width * 2.0f * scale);
    for (const Point2f &film : {Point2f(32.0f, 32.0f), Point2f(10.5f, 50.25f)}) {
        Ray3f ray;
        scene->getCamera()->sampleRayDifferential(ray, film, Point2f(0.5f, 0.5f));
        REQUIRE(ray.hasDifferentials);
        Intersection its;
        REQUIRE(scene->rayIntersect(ray, its));
        // Off-centre pixels see a slightly smaller pixel footprint (the image plane is flat,
        // the pixel's solid angle shrinks as cos³): within 3% up to 20° off axis.
        const float tolerance = film == Point2f(32.0f, 32.0f) ? 1e-3f : 0.03f;
        CHECK(std::abs(its.dudx) == Approx(expected).epsilon(tolerance));
        CHECK(std::abs(its.dvdy) == Approx(expected).epsilon(tolerance));
        CHECK(std::abs(its.dudy) < 1e-3f * expected);
        CHECK(std::abs(its.dvdx) < 1e-3f * expected);
    }
    // Without differentials there is no footprint.
    Ray3f plain;
    scene->getCamera()->sampleRay(plain, Point2f(32.0f, 32.0f), Point2f(0.5f, 0.5f));
    Intersection its;
    REQUIRE(scene->rayIntersect(plain, its));
    CHECK(its.dudx == 0.0f);
}

TEST_CASE("A flat mirror carries the footprint: the plane seen in it at d1 + d2 looks as "
          "at distance d1 + d2",
          "[texture][differentials]") {
    const float fov = 30.0f;
    auto footprint = [&](const std::string &mirror, float planeZ) {
        auto scene = loadScene(fmt::format(R"(<scene> <integrator type="normals"/> {}
            {}
            <mesh type="obj"><string name="filename" value="meshes/floor.obj"/>
                <transform name="toWorld"><rotate axis="1, 0, 0" angle="90"/><scale value="50"/>
                    <translate value="0, 0, {}"/></transform>
            </mesh></scene>)",
                                           cameraOnZAxis(fov, 32, 4.0f), mirror, planeZ),
                               kSceneDirectory);
        Ray3f ray;
        scene->getCamera()->sampleRayDifferential(ray, Point2f(16.0f, 16.0f), Point2f(0.5f, 0.5f));
        Intersection its;
        REQUIRE(scene->rayIntersect(ray, its));
        if (its.shape->getBSDF()->toString().find("Mirror") != std::string::npos) {
            BSDFQueryRecord bRec(its, its.toLocal(-ray.d));
            its.shape->getBSDF()->sample(bRec, Point2f(0.5f, 0.5f));
            const Ray3f reflected = spawnScatteredRay(its, ray, bRec);
            REQUIRE(scene->rayIntersect(reflected, its));
        }
        return std::abs(its.dudx);
    };
    // A mirror facing the camera at z = 0, tilted 45° about y, sends the view to a plane at
    // x = −3 (facing +x); compare with that plane seen straight at distance 4 + 3.
    const float viaMirror =
        footprint(R"(<mesh type="obj"><string name="filename" value="meshes/floor.obj"/>
            <transform name="toWorld"><rotate axis="1, 0, 0" angle="90"/><rotate axis="0, 1, 0" angle="-45"/></transform>
            <bsdf type="mirror"/></mesh>
        <mesh type="obj"><string name="filename" value="meshes/floor.obj"/>
            <transform name="toWorld"><rotate axis="1, 0, 0" angle="90"/><rotate axis="0, 1, 0" angle="90"/>
                <scale value="50"/><translate value="-3, 0, 0"/></transform></mesh>)",
                  -1000.0f);
    const float direct = footprint("", -3.0f);
    CHECK(viaMirror == Approx(direct).epsilon(1e-3));
}

TEST_CASE("A normal map of one tilted normal shades like the tilted geometry (t-test)",
          "[texture][normalmap][ttest]") {
    // A diffuse point lit by a sphere light wholly above its tangent plane has radiance
    // albedo·L·(r/d)²·cos θ (the sphere's form factor): the reference for both scenes.
    const float tilt = 30.0f, albedo = 0.5f, L = 10.0f, r = 0.5f;
    const Vector3f light(3.0f, 4.0f, 1.0f);
    auto scene = [&](const std::string &surface) {
        return loadScene(fmt::format(R"(<scene>
            <integrator type="direct_ems"/>
            <sampler type="independent"><integer name="sampleCount" value="1"/></sampler>
            <camera type="perspective"><float name="fov" value="0.001"/>
                <integer name="width" value="1"/> <integer name="height" value="1"/>
                <transform name="toWorld"><lookat origin="0.5, 3, 2" target="0, 0, 0" up="0, 1, 0"/></transform>
            </camera>
            <mesh type="obj"><string name="filename" value="meshes/floor.obj"/> {}
                <bsdf type="diffuse"><color name="albedo" value="{}"/></bsdf></mesh>
            <mesh type="sphere"><point name="center" value="{}, {}, {}"/><float name="radius" value="{}"/>
                <emitter type="area"><color name="radiance" value="{}"/></emitter></mesh>
            </scene>)",
                                     surface, albedo, light.x(), light.y(), light.z(), r, L),
                         kSceneDirectory);
    };
    // Tangent space of floor.obj: s = +x (dp/du), t = −z (dp/dv), n = +y. The tilted
    // normal (sin, 0, cos) in tangent space is (sin, cos, 0) in the world: the geometry
    // turned by −tilt about z.
    auto normalMapped = [&](float degrees) {
        const float s = std::sin(degToRad(degrees)), c = std::cos(degToRad(degrees));
        return fmt::format(R"(<transform name="toWorld"><scale value="10"/></transform>
            <texture type="constant" name="normal"><color name="value" value="{}, 0.5, {}"/></texture>)",
                           0.5f + 0.5f * s, 0.5f + 0.5f * c);
    };
    const std::string tilted = fmt::format(
        R"(<transform name="toWorld"><scale value="10"/><rotate axis="0, 0, 1" angle="{}"/></transform>)",
        -tilt);
    const Vector3f n(std::sin(degToRad(tilt)), std::cos(degToRad(tilt)), 0.0f);
    const float d = light.norm();
    const double reference = albedo * L * (r / d) * (r / d) * n.dot(light / d);

    const size_t samples = 40000;
    const RunningMoments geometry = estimatePixel(*scene(tilted), samples);
    const RunningMoments mapped = estimatePixel(*scene(normalMapped(tilt)), samples);
    const RunningMoments wrong = estimatePixel(*scene(normalMapped(tilt + 5.0f)), samples);
    const double alpha = 0.01;
    const StudentTResult g =
        studentTTest(geometry.mean, geometry.variance(), samples, reference, alpha);
    const StudentTResult m =
        studentTTest(mapped.mean, mapped.variance(), samples, reference, alpha);
    const StudentTResult w = studentTTest(wrong.mean, wrong.variance(), samples, reference, alpha);
    INFO("reference " << reference << ", tilted geometry " << geometry.mean << " (t = " << g.t
                      << "), normal map " << mapped.mean << " (t = " << m.t << "), 5° off "
                      << wrong.mean << " (t = " << w.t << ")");
    CHECK(g.passed);
    CHECK(m.passed);
    CHECK_FALSE(w.passed); // the control: a normal 5° off is told apart
}

TEST_CASE("A grazing checkerboard at 1 spp: MIP mapping keeps the far-field mean and cuts "
          "the variance",
          "[texture][mipmap][render]") {
    TempDir dir;
    // 32×32 texels, 4×4 cells of 0 and 1 (mean 0.5), as a linear EXR.
    Bitmap checker(Eigen::Vector2i(32, 32));
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x)
            checker(y, x) = Color3f(((x / 8 + y / 8) % 2) ? 1.0f : 0.0f);
    checker.saveEXR((dir.path() / "checker.exr").string());
    std::filesystem::copy(kSceneDirectory + "/meshes/floor.obj", dir.path() / "floor.obj");

    // The floor emits its texture, so a pixel's value is the filtered texture itself.
    auto render = [&](const std::string &filter) {
        auto scene = loadScene(fmt::format(R"(<scene>
            <integrator type="path_mats"><integer name="maxDepth" value="1"/></integrator>
            <sampler type="independent"><integer name="sampleCount" value="1"/></sampler>
            <camera type="perspective"><float name="fov" value="40"/>
                <integer name="width" value="256"/> <integer name="height" value="128"/>
                <transform name="toWorld"><lookat origin="0, 0.5, 0" target="0, 0.5, -10" up="0, 1, 0"/></transform>
                <rfilter type="box"/>
            </camera>
            <mesh type="obj"><string name="filename" value="floor.obj"/>
                <transform name="toWorld"><scale value="500"/></transform>
                <float name="uvScale" value="500"/>
                <bsdf type="diffuse"><color name="albedo" value="0"/></bsdf>
                <emitter type="area">
                    <texture type="image" name="radiance"><string name="filename" value="checker.exr"/>
                        <string name="filter" value="{}"/></texture>
                </emitter>
            </mesh></scene>)",
                                           filter),
                               dir.path().string());
        RenderOptions options;
        return renderScene(*scene, options).image;
    };
    // The far field: rows 66..81, about 60 to 4 units away (the horizon is row 64).
    auto farField = [](const Bitmap &image) {
        RunningMoments moments;
        for (int y = 66; y < 82; ++y)
            for (int x = 0; x < image.width(); ++x)
                moments.add(image(y, x).r());
        return moments;
    };
    const RunningMoments nearest = farField(render("nearest"));
    const RunningMoments trilinear = farField(render("trilinear"));
    const RunningMoments ewa = farField(render("ewa"));
    std::cout << fmt::format("grazing checkerboard, far field at 1 spp: mean / variance: "
                             "nearest {:.4f} / {:.5f}, trilinear {:.4f} / {:.5f}, "
                             "EWA {:.4f} / {:.5f}; variance ratio nearest/trilinear {:.1f}, "
                             "nearest/EWA {:.1f}\n",
                             nearest.mean, nearest.variance(), trilinear.mean, trilinear.variance(),
                             ewa.mean, ewa.variance(), nearest.variance() / trilinear.variance(),
                             nearest.variance() / ewa.variance());
    // 4096 pixels of variance ≤ 0.25: the mean's standard error is ≤ 0.008; 4σ.
    CHECK(nearest.mean == Approx(0.5).margin(0.032));
    CHECK(trilinear.mean == Approx(0.5).margin(0.032));
    CHECK(ewa.mean == Approx(0.5).margin(0.032));
    // Unfiltered, each pixel is 0 or 1 (variance 1/4); filtered, close to the mean.
    CHECK(nearest.variance() > 0.2);
    CHECK(nearest.variance() > 10.0 * trilinear.variance());
    CHECK(nearest.variance() > 10.0 * ewa.variance());
}

TEST_CASE("A textured roughness keeps the BSDF's chi-square test passing", "[texture][chi2]") {
    auto bsdf = std::dynamic_pointer_cast<BSDF>(loadFromXMLString(R"(<bsdf type="roughconductor">
        <texture type="checkerboard_float" name="alpha"><float name="value1" value="0.1"/>
            <float name="value2" value="0.5"/></texture></bsdf>)"));
    REQUIRE(bsdf);
    const TextureQuery smooth(Point2f(0.5f, 0.5f)), rough(Point2f(1.5f, 0.5f));
    const Vector3f wi = Vector3f(std::sin(0.6f), 0.0f, std::cos(0.6f));
    ChiSquareOptions options;
    options.sampleCount = 300000;
    options.significanceLevel = sidakCorrection(0.01, 2);
    for (const TextureQuery &where : {smooth, rough}) {
        options.seed += 1;
        const ChiSquareReport report = runChiSquareTest(bsdfRoutine(*bsdf, wi, where), options);
        INFO("uv " << where.uv.transpose() << ": " << report.result.message);
        CHECK(report.result.passed);
    }
    // The control: sampling one texel's roughness against the other's pdf is rejected.
    SamplingRoutine mixed = bsdfRoutine(*bsdf, wi, smooth);
    mixed.pdf = bsdfRoutine(*bsdf, wi, rough).pdf;
    options.seed += 1;
    CHECK_FALSE(runChiSquareTest(mixed, options).result.passed);
}

TEST_CASE("A bump map of a linear ramp tilts the shading normal like the slope it encodes",
          "[texture][bumpmap]") {
    TempDir dir;
    // h(u) = u, sampled at texel centres: bilinear interpolation reproduces it exactly.
    Bitmap ramp(Eigen::Vector2i(64, 4));
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 64; ++x)
            ramp(y, x) = Color3f((x + 0.5f) / 64.0f);
    ramp.saveEXR((dir.path() / "ramp.exr").string());
    std::filesystem::copy(kSceneDirectory + "/meshes/floor.obj", dir.path() / "floor.obj");
    for (float bumpScale : {0.5f, 1.0f, -2.0f}) {
        CAPTURE(bumpScale);
        auto scene = loadScene(fmt::format(R"(<scene> <integrator type="normals"/>
            <camera type="perspective"><integer name="width" value="8"/><integer name="height" value="8"/></camera>
            <mesh type="obj"><string name="filename" value="floor.obj"/>
                <float name="bumpScale" value="{}"/>
                <texture type="image" name="bump"><string name="filename" value="ramp.exr"/>
                    <string name="filter" value="bilinear"/> <string name="wrap" value="clamp"/></texture>
            </mesh></scene>)",
                                           bumpScale),
                               dir.path().string());
        Intersection its;
        REQUIRE(scene->rayIntersect(Ray3f(Point3f(0.1f, 1.0f, 0.2f), Vector3f(0.0f, -1.0f, 0.0f)),
                                    its));
        // floor.obj: dp/du = (2, 0, 0), dp/dv = (0, 0, −2). Displacing by s·h(u) along +y
        // gives dp'/du = (2, s, 0), so n' ∝ dp'/du × dp/dv ∝ (−s, 2, 0).
        const Vector3f expected = Vector3f(-bumpScale, 2.0f, 0.0f).normalized();
        CHECK(its.shFrame.n.isApprox(expected, 1e-3f));
        CHECK(its.geoFrame.n.isApprox(Vector3f(0.0f, 1.0f, 0.0f)));
    }
}

TEST_CASE("Rays carry differentials only in scenes with footprint-filtered textures",
          "[texture][differentials]") {
    for (const auto &[filter, expected] :
         {std::pair{"trilinear", true}, std::pair{"ewa", true}, std::pair{"nearest", false}}) {
        CAPTURE(filter);
        auto scene = std::dynamic_pointer_cast<Scene>(loadFromXML(
            kSceneDirectory + "/textured.xml", LoadOptions(Defines{{"filter", filter}})));
        REQUIRE(scene);
        Ray3f ray;
        scene->sampleCameraRay(ray, Point2f(320.0f, 200.0f), Point2f(0.5f, 0.5f));
        CHECK(ray.hasDifferentials == expected);
    }
    auto cbox = std::dynamic_pointer_cast<Scene>(
        loadFromXML(std::string(NORI_SOURCE_DIR) + "/scenes/cbox/cbox.xml"));
    Ray3f ray;
    cbox->sampleCameraRay(ray, Point2f(10.0f, 10.0f), Point2f(0.5f, 0.5f));
    CHECK_FALSE(ray.hasDifferentials);
}

TEST_CASE("miplevel shows the level of a head-on plane: log2 of 2 texels per pixel step",
          "[texture][mipmap][differentials]") {
    TempDir dir;
    Bitmap image(Eigen::Vector2i(256, 256));
    image.setConstant(Color3f(0.5f));
    image.saveEXR((dir.path() / "grey.exr").string());
    std::filesystem::copy(kSceneDirectory + "/meshes/floor.obj", dir.path() / "floor.obj");
    const float d = 5.0f, fov = 40.0f, scale = 2.0f;
    const int width = 32;
    auto scene = loadScene(
        fmt::format(
            R"(<scene> <integrator type="miplevel"><boolean name="raw" value="true"/></integrator>
        {} <mesh type="obj"><string name="filename" value="floor.obj"/>
            <transform name="toWorld"><rotate axis="1, 0, 0" angle="90"/><scale value="{}"/></transform>
            <bsdf type="diffuse"><texture type="image" name="albedo">
                <string name="filename" value="grey.exr"/></texture></bsdf>
        </mesh></scene>)",
            cameraOnZAxis(fov, width, d), scale),
        dir.path().string());
    // du/dx per pixel (see the head-on test) times 256 texels, doubled (pbrt-v3 §10.4.3).
    const float dudx = 2.0f * d * std::tan(degToRad(fov / 2.0f)) / (width * 2.0f * scale);
    const float expected = std::log2(2.0f * dudx * 256.0f);
    REQUIRE(expected > 1.0f);
    Ray3f ray;
    scene->sampleCameraRay(ray, Point2f(16.0f, 16.0f), Point2f(0.5f, 0.5f));
    const Color3f level = scene->getIntegrator()->Li(scene.get(), nullptr, ray);
    CHECK(level.r() == Approx(expected).epsilon(1e-3));
}
