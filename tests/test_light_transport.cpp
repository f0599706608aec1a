// Integrators against analytic answers, through Nori-format ttest XML: a white furnace
// (an emitting, reflecting sphere seen from inside), a point light over a plane (inverse
// square law), a polygonal area light over a plane (Lambert's formula), and average
// visibility under a sphere. Every path and direct integrator must match the reference;
// path_mats, path_ems and path_mis therefore agree with each other.
#include <nori/parser.h>
#include <nori/scene.h>
#include <nori/statistics.h>
#include <nori/test.h>

#include "testutil.h"

#include <catch2/catch.hpp>

using namespace nori;
using nori::testing::TempDir;

namespace {

/// Runs a ttest of `integrator` on the scene content against `reference`.
bool tTest(const std::string &integrator, const std::string &sceneContent, double reference,
           const std::string &directory = ".", int samples = 40000) {
    const std::string xml = fmt::format(R"(<test type="ttest">
        <string name="references" value="{}"/>
        <integer name="sampleCount" value="{}"/>
        <scene>{}{}</scene></test>)",
                                        reference, samples, integrator, sceneContent);
    auto test = std::dynamic_pointer_cast<Test>(loadFromXMLString(xml, directory));
    REQUIRE(test);
    return test->run();
}

/// A 1x1 camera with a tiny field of view at `origin`, looking at `target`.
std::string pinpointCamera(const std::string &origin, const std::string &target,
                           const std::string &up = "0, 1, 0") {
    return fmt::format(R"(<camera type="perspective">
        <integer name="width" value="1"/><integer name="height" value="1"/>
        <float name="fov" value="0.001"/>
        <transform name="toWorld"><lookat origin="{}" target="{}" up="{}"/></transform>
    </camera>)",
                       origin, target, up);
}

/// A floor of albedo 0.6: the 200 x 200 quad floor.obj at y = 0 (written by FloorDir).
const char *kFloor = R"(<mesh type="obj"><string name="filename" value="floor.obj"/>
    <bsdf type="diffuse"><color name="albedo" value="0.6"/></bsdf></mesh>)";

/// A temporary folder holding floor.obj.
struct FloorDir : TempDir {
    FloorDir() {
        write("floor.obj", "v -100 0 -100\nv -100 0 100\nv 100 0 100\nv 100 0 -100\nf 1 2 3 4\n");
    }
    std::string folder() const { return path().string(); }
};

/// Irradiance at the origin (normal +y) from a polygon of radiance Le, by Lambert's
/// formula E = (Le/2) |Σ θᵢ (n · γᵢ)|.
double lambertIrradiance(const std::vector<Point3f> &polygon, double radiance) {
    const Vector3f n(0.0f, 1.0f, 0.0f);
    double sum = 0.0;
    for (size_t i = 0; i < polygon.size(); ++i) {
        const Vector3f a = Vector3f(polygon[i]).normalized();
        const Vector3f b = Vector3f(polygon[(i + 1) % polygon.size()]).normalized();
        const double theta = std::acos(std::clamp(static_cast<double>(a.dot(b)), -1.0, 1.0));
        sum += theta * n.dot(a.cross(b).normalized());
    }
    return 0.5 * radiance * std::abs(sum);
}

std::string objQuad(const std::vector<Point3f> &quad) {
    std::string obj;
    for (const Point3f &p : quad)
        obj += fmt::format("v {} {} {}\n", p.x(), p.y(), p.z());
    return obj + "f 1 2 3 4\n";
}

const std::vector<std::string> kPathIntegrators = {"path_mats", "path_ems", "path_mis"};
const std::vector<std::string> kDirectIntegrators = {"direct_mats", "direct_ems", "direct_mis",
                                                     "direct", "whitted"};

} // namespace

TEST_CASE("White furnace: an emitting sphere of albedo a seen from inside", "[integrator][ttest]") {
    // Every point emits Le and reflects a fraction a of what arrives, uniformly, so the
    // radiance is Le(1 + a + a² + …) = Le/(1 − a) = 1 for Le = a = 1/2 (pbrt's analytic
    // test). Direct lighting stops after one bounce: Le(1 + a) = 0.75.
    const std::string scene = pinpointCamera("0.2, -0.1, 0.3", "1, 0.4, -0.2") + R"(
        <mesh type="sphere"><float name="radius" value="1"/><boolean name="flipNormals" value="true"/>
            <bsdf type="diffuse"><color name="albedo" value="0.5"/></bsdf>
            <emitter type="area"><color name="radiance" value="0.5"/></emitter></mesh>)";
    for (const std::string &name : kPathIntegrators) {
        INFO(name);
        CHECK(tTest("<integrator type=\"" + name + "\"/>", scene, 1.0));
    }
    for (const std::string &name : kDirectIntegrators) {
        INFO(name);
        CHECK(tTest("<integrator type=\"" + name + "\"/>", scene, 0.75));
    }
    // A maximum depth cuts the series: 2 bounces give Le(1 + a + a²) = 0.875.
    CHECK(tTest(R"(<integrator type="path_mis"><integer name="maxDepth" value="2"/></integrator>)",
                scene, 0.875));
    // Negative control: the t-test rejects the direct-lighting value for a path tracer.
    CHECK_FALSE(tTest("<integrator type=\"path_mis\"/>", scene, 0.75));
}

TEST_CASE("White furnace: inside a closed box that emits and reflects", "[integrator][ttest]") {
    // The same series inside a cube of 12 triangles (sampled by area, not by a cone):
    // Le/(1 − a) for the path tracers, Le(1 + a) for direct lighting.
    TempDir dir;
    dir.write("box.obj", "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\n"
                         "v -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
                         // Faces wound so their normals point into the box.
                         "f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 4 3 7 8\nf 1 4 8 5\nf 2 6 7 3\n");
    const std::string scene = pinpointCamera("0.3, 0.2, -0.1", "-1, 0.5, 0.4") + R"(
        <mesh type="obj"><string name="filename" value="box.obj"/>
            <bsdf type="diffuse"><color name="albedo" value="0.6"/></bsdf>
            <emitter type="area"><color name="radiance" value="0.4"/></emitter></mesh>)";
    for (const std::string &name : kPathIntegrators) {
        INFO(name);
        CHECK(tTest("<integrator type=\"" + name + "\"/>", scene, 1.0, dir.path().string()));
    }
    for (const std::string &name : kDirectIntegrators) {
        INFO(name);
        CHECK(tTest("<integrator type=\"" + name + "\"/>", scene, 0.4 * 1.6, dir.path().string()));
    }
}

TEST_CASE("White furnace: a box whose vertex normals point inward, against its winding",
          "[integrator][ttest]") {
    // The course's furnace: the triangles wind outward but every `vn` points into the box,
    // and the normals decide the front side (Nori 2, pbrt). With Le = 1 and albedo 1/2
    // the box glows Le/(1 − a) = 2 for path tracers and Le(1 + a) = 1.5 for direct
    // lighting. Before the fix it was black (mean 1e-13).
    TempDir dir;
    dir.write("box.obj", "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\n"
                         "v -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
                         "vn 0 0 1\nvn 0 0 -1\nvn 0 1 0\nvn 0 -1 0\nvn 1 0 0\nvn -1 0 0\n"
                         // Wound outward (−z face: 1 4 3 2 has normal −z), vn inward.
                         "f 1//1 4//1 3//1 2//1\nf 5//2 6//2 7//2 8//2\n"
                         "f 1//3 2//3 6//3 5//3\nf 4//4 8//4 7//4 3//4\n"
                         "f 1//5 5//5 8//5 4//5\nf 2//6 3//6 7//6 6//6\n");
    const std::string scene = pinpointCamera("0.3, 0.2, -0.1", "-1, 0.5, 0.4") + R"(
        <mesh type="obj"><string name="filename" value="box.obj"/>
            <bsdf type="diffuse"><color name="albedo" value="0.5"/></bsdf>
            <emitter type="area"><color name="radiance" value="1"/></emitter></mesh>)";
    for (const std::string &name : kPathIntegrators) {
        INFO(name);
        CHECK(tTest("<integrator type=\"" + name + "\"/>", scene, 2.0, dir.path().string()));
    }
    for (const std::string &name : kDirectIntegrators) {
        INFO(name);
        CHECK(tTest("<integrator type=\"" + name + "\"/>", scene, 1.5, dir.path().string()));
    }
    // Negative control: the dark box (the old behaviour) is rejected.
    CHECK_FALSE(tTest("<integrator type=\"path_mis\"/>", scene, 0.0, dir.path().string()));
}

TEST_CASE("ttest: a deterministic estimate passes against a reference rounded as staff do",
          "[integrator][ttest]") {
    // A 1x1 camera with a fov of 1e-9 degrees sees one point; a point light makes every
    // sample the same value, exactly (a/π)·I·cos θ/d². Staff files give it to 4 digits.
    const double exact = 0.6 / kPiDouble * 10.0 * (2.0 / std::sqrt(4.25)) / 4.25;
    const double rounded = std::round(exact * 1e4) / 1e4;
    REQUIRE(rounded != exact);
    FloorDir dir;
    const std::string scene = R"(<camera type="perspective">
        <integer name="width" value="1"/><integer name="height" value="1"/>
        <float name="fov" value="1e-9"/>
        <transform name="toWorld"><lookat origin="3, 1, 2" target="0, 0, 0"/></transform>
    </camera>)" + std::string(kFloor) +
                              R"(<emitter type="point"><point name="position" value="0.5, 2, 0"/>
            <color name="intensity" value="10"/></emitter>)";
    CHECK(tTest("<integrator type=\"direct\"/>", scene, rounded, dir.folder(), 10000));
    // Nori 2's variance floor of 1e-5 makes t = |mean − reference|·√(n/1e-5): the
    // rounding (< 5e-5) gives t < 1.6, a 1% error (4.4e-3) gives t = 138: rejected.
    CHECK_FALSE(tTest("<integrator type=\"direct\"/>", scene, exact * 1.01, dir.folder(), 10000));
}

TEST_CASE("A point light over a plane follows the inverse-square law", "[integrator][ttest]") {
    // L = (a/π) · I cos θ / d², with I = 10, a = 0.6, the light at (0.5, 2, 0) and the
    // point seen at the origin: d² = 4.25, cos θ = 2/√4.25.
    const double reference = 0.6 / kPiDouble * 10.0 * (2.0 / std::sqrt(4.25)) / 4.25;
    FloorDir dir;
    const std::string scene = pinpointCamera("3, 1, 2", "0, 0, 0") + kFloor + R"(
        <emitter type="point"><point name="position" value="0.5, 2, 0"/>
            <color name="intensity" value="10"/></emitter>)";
    // Only strategies that sample lights can see a point light.
    for (const char *name :
         {"direct_ems", "direct_mis", "direct", "whitted", "path_ems", "path_mis"}) {
        INFO(name);
        CHECK(tTest(std::string("<integrator type=\"") + name + "\"/>", scene, reference,
                    dir.folder()));
    }
    // 'power' is 4π times the intensity.
    const std::string byPower = pinpointCamera("3, 1, 2", "0, 0, 0") + kFloor + R"(
        <emitter type="point"><point name="position" value="0.5, 2, 0"/>
            <color name="power" value="125.66370614"/></emitter>)";
    CHECK(tTest("<integrator type=\"path_mis\"/>", byPower, reference, dir.folder()));
}

TEST_CASE("A polygonal area light over a plane matches Lambert's formula", "[integrator][ttest]") {
    // A quad light at height 1.5 facing down, offset from the shaded point at the origin.
    FloorDir dir;
    const std::vector<Point3f> quad = {
        {-0.2f, 1.5f, -0.4f}, {0.8f, 1.5f, -0.4f}, {0.8f, 1.5f, 0.3f}, {-0.2f, 1.5f, 0.3f}};
    dir.write("light.obj", objQuad(quad));
    // Lambert (1760): E = (Le/2) Σ θᵢ (n · γᵢ), θᵢ the angle edge i subtends at the point
    // and γᵢ the unit normal of the plane through the point and that edge.
    const double radiance = 3.0, albedo = 0.6;
    const double irradiance = lambertIrradiance(quad, radiance);
    const double reference = albedo / kPiDouble * irradiance;
    const std::string scene = pinpointCamera("2, 1, 3", "0, 0, 0") + kFloor + R"(
        <mesh type="obj"><string name="filename" value="light.obj"/>
            <bsdf type="diffuse"><color name="albedo" value="0"/></bsdf>
            <emitter type="area"><color name="radiance" value="3"/></emitter></mesh>)";
    for (const auto *list : {&kPathIntegrators, &kDirectIntegrators})
        for (const std::string &name : *list) {
            INFO(name << " reference " << reference);
            CHECK(tTest("<integrator type=\"" + name + "\"/>", scene, reference,
                        dir.path().string()));
        }
}

TEST_CASE("Several lights of very unequal power: Lambert's formula per light, summed",
          "[integrator][ttest]") {
    // Lights are picked in proportion to their power, so the dim ones are rarely sampled;
    // every light must still count exactly once. A bright small quad, a dim large quad
    // (power ratio ~300) and, for the strategies that can see it, a dim point light.
    FloorDir dir;
    const std::vector<Point3f> bright = {
        {0.3f, 1.2f, -0.2f}, {0.6f, 1.2f, -0.2f}, {0.6f, 1.2f, 0.1f}, {0.3f, 1.2f, 0.1f}};
    const std::vector<Point3f> dim = {
        {-1.5f, 2.0f, -1.0f}, {0.5f, 2.0f, -1.0f}, {0.5f, 2.0f, 1.0f}, {-1.5f, 2.0f, 1.0f}};
    dir.write("bright.obj", objQuad(bright));
    dir.write("dim.obj", objQuad(dim));
    const double albedo = 0.6, brightLe = 40.0, dimLe = 0.3;
    const double areaLights =
        albedo / kPiDouble * (lambertIrradiance(bright, brightLe) + lambertIrradiance(dim, dimLe));
    // A point light of intensity 0.2 at (−0.5, 1, 0.5): E = I cos θ / d².
    const double pointLight = albedo / kPiDouble * 0.2 * (1.0 / std::sqrt(1.5)) / 1.5;
    const std::string lights = R"(
        <mesh type="obj"><string name="filename" value="bright.obj"/>
            <bsdf type="diffuse"><color name="albedo" value="0"/></bsdf>
            <emitter type="area"><color name="radiance" value="40"/></emitter></mesh>
        <mesh type="obj"><string name="filename" value="dim.obj"/>
            <bsdf type="diffuse"><color name="albedo" value="0"/></bsdf>
            <emitter type="area"><color name="radiance" value="0.3"/></emitter></mesh>)";
    const std::string point = R"(<emitter type="point"><point name="position" value="-0.5, 1, 0.5"/>
            <color name="intensity" value="0.2"/></emitter>)";
    const std::string camera = pinpointCamera("2, 1, 3", "0, 0, 0");
    for (const auto *list : {&kPathIntegrators, &kDirectIntegrators})
        for (const std::string &name : *list) {
            INFO(name << ", area lights only: " << areaLights);
            CHECK(tTest("<integrator type=\"" + name + "\"/>", camera + kFloor + lights, areaLights,
                        dir.folder(), 100000));
        }
    for (const char *name : {"direct_ems", "direct_mis", "whitted", "path_ems", "path_mis"}) {
        INFO(name << ", with the point light: " << areaLights + pointLight);
        CHECK(tTest(std::string("<integrator type=\"") + name + "\"/>",
                    camera + kFloor + lights + point, areaLights + pointLight, dir.folder(),
                    100000));
    }
    // Negative control: the answer without the dim light is rejected.
    const double withoutDim = albedo / kPiDouble * lambertIrradiance(bright, brightLe);
    CHECK_FALSE(tTest("<integrator type=\"path_mis\"/>", camera + kFloor + lights, withoutDim,
                      dir.folder(), 100000));
}

TEST_CASE("Mirror and glass furnaces: a specular sphere in a uniformly emitting room sees 1",
          "[integrator][ttest]") {
    // Every path ends on the room's walls, which emit 1 and absorb everything, so any
    // specular chain (mirror, or glass with its η² radiance scaling in and out) sees 1.
    const std::string room = R"(
        <mesh type="sphere"><float name="radius" value="5"/><boolean name="flipNormals" value="true"/>
            <bsdf type="diffuse"><color name="albedo" value="0"/></bsdf>
            <emitter type="area"><color name="radiance" value="1"/></emitter></mesh>)";
    const std::string camera = pinpointCamera("0, 0, 3", "0.1, 0.2, 0");
    const std::string mirror = R"(<mesh type="sphere"><bsdf type="mirror"/></mesh>)";
    const std::string glass = R"(<mesh type="sphere"><bsdf type="dielectric"/></mesh>)";
    // One specular bounce reaches the wall: every integrator follows a mirror.
    for (const auto *list : {&kPathIntegrators, &kDirectIntegrators})
        for (const std::string &name : *list) {
            INFO(name << " and a mirror");
            CHECK(tTest("<integrator type=\"" + name + "\"/>", camera + room + mirror, 1.0));
        }
    // Glass needs two refractions: the path tracers and Whitted's recursion.
    for (const std::string name : {"path_mats", "path_ems", "path_mis", "whitted"}) {
        INFO(name << " and glass");
        CHECK(tTest("<integrator type=\"" + name + "\"/>", camera + room + glass, 1.0));
    }
    // Negative control: a one-bounce integrator loses the refracted light.
    CHECK_FALSE(tTest("<integrator type=\"direct_mis\"/>", camera + room + glass, 1.0));
}

TEST_CASE("A spherical light over a plane (cone sampling) matches its closed form",
          "[integrator][ttest]") {
    // A sphere of radius r and radiance Le straight above the point, centre at height h,
    // gives irradiance E = π Le (r/h)² (the cap's projected solid angle, sin²α).
    const double r = 0.4, h = 1.5, radiance = 2.0, albedo = 0.6;
    const double reference = albedo / kPiDouble * kPiDouble * radiance * (r / h) * (r / h);
    FloorDir dir;
    const std::string scene = pinpointCamera("3, 1, 2", "0, 0, 0") + kFloor + R"(
        <mesh type="sphere"><point name="center" value="0, 1.5, 0"/><float name="radius" value="0.4"/>
            <bsdf type="diffuse"><color name="albedo" value="0"/></bsdf>
            <emitter type="area"><color name="radiance" value="2"/></emitter></mesh>)";
    for (const auto *list : {&kPathIntegrators, &kDirectIntegrators})
        for (const std::string &name : *list) {
            INFO(name << " reference " << reference);
            CHECK(tTest("<integrator type=\"" + name + "\"/>", scene, reference, dir.folder()));
        }
}

TEST_CASE("Average visibility under a sphere is cos α", "[integrator][ttest]") {
    // Uniform hemisphere directions: the sphere (r = 1 at height h = 2) covers the cap
    // θ < α = asin(1/2), a fraction 1 − cos α of the hemisphere's solid angle.
    FloorDir dir;
    const std::string scene = pinpointCamera("5, 0.5, 0", "0, 0, 0") + kFloor + R"(
        <mesh type="sphere"><point name="center" value="0, 2, 0"/></mesh>)";
    CHECK(tTest(R"(<integrator type="av"><float name="length" value="100"/></integrator>)", scene,
                std::cos(std::asin(0.5)), dir.folder()));
    // Occluders beyond `length` do not count.
    CHECK(tTest(R"(<integrator type="av"><float name="length" value="0.5"/></integrator>)", scene,
                1.0, dir.folder()));
}

namespace {

/// A t-test over the means of `pixels` pixels of `spp` samples each (sample indices
/// 0, ..., spp − 1 of pixel (i, 0)): samples within a pixel are correlated by design
/// under stratified and Sobol' sampling, but pixel means are independent estimates.
StudentTResult pixelMeansTTest(Scene &scene, double reference, int pixels, uint32_t spp) {
    scene.getIntegrator()->preprocess(&scene);
    std::unique_ptr<Sampler> sampler = scene.getSampler()->clone();
    RunningMoments means;
    for (int pixel = 0; pixel < pixels; ++pixel) {
        double sum = 0.0;
        for (uint32_t index = 0; index < spp; ++index) {
            sampler->generate(Point2i(pixel, 0), index);
            sampler->next2D(); // the film position: the 1x1 camera's view is uniform
            Ray3f ray;
            Color3f value = scene.sampleCameraRay(ray, Point2f(0.5f, 0.5f), sampler->next2D());
            value *= scene.getIntegrator()->Li(&scene, sampler.get(), ray);
            sum += value.getLuminance();
        }
        means.add(sum / spp);
    }
    return studentTTest(means.mean, means.variance(), means.count, reference, 0.01);
}

} // namespace

TEST_CASE("Stratified and Sobol' samples keep the integrators unbiased", "[integrator][ttest]") {
    // Lambert's formula for a quad light over the floor, as above.
    FloorDir dir;
    const std::vector<Point3f> quad = {
        {-0.2f, 1.5f, -0.4f}, {0.8f, 1.5f, -0.4f}, {0.8f, 1.5f, 0.3f}, {-0.2f, 1.5f, 0.3f}};
    dir.write("light.obj", objQuad(quad));
    const double reference = 0.6 / kPiDouble * lambertIrradiance(quad, 3.0);
    for (const std::string sampler : {"stratified", "sobol", "independent"})
        for (const std::string integrator : {"direct_ems", "direct_mis", "path_mis", "path_mats"}) {
            CAPTURE(sampler, integrator);
            auto scene = std::dynamic_pointer_cast<Scene>(loadFromXMLString(
                fmt::format(R"(<scene><integrator type="{}"/>
                    <sampler type="{}"><integer name="sampleCount" value="16"/></sampler>{}{}
                    <mesh type="obj"><string name="filename" value="light.obj"/>
                        <bsdf type="diffuse"><color name="albedo" value="0"/></bsdf>
                        <emitter type="area"><color name="radiance" value="3"/></emitter></mesh>
                    </scene>)",
                            integrator, sampler, pinpointCamera("2, 1, 3", "0, 0, 0"), kFloor),
                dir.folder()));
            REQUIRE(scene);
            const StudentTResult result = pixelMeansTTest(*scene, reference, 2000, 16);
            INFO("t = " << result.t);
            CHECK(result.passed);
            // Control: 5% off is rejected (the test has the power to see it; path_mats,
            // which finds the small light by BSDF sampling only, is the noisiest).
            CHECK_FALSE(pixelMeansTTest(*scene, reference * 1.05, 2000, 16).passed);
        }
}
