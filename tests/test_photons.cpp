// Photon mapping: photon emission of every light against its power (t-test) and its
// emission distribution (χ²), the kd-tree against brute force, and the photon mappers
// against closed forms: a diffuse plane under a spherical light (Lambert), the white
// furnace, and a caustic against path_mis. Each statistical test has a negative control.
#include "testing/halfbuffers.h"
#include "testutil.h"

#include <nori/bitmap.h>
#include <nori/bsdf.h>
#include <nori/chisquare.h>
#include <nori/emitter.h>
#include <nori/frame.h>
#include <nori/parser.h>
#include <nori/pcg32.h>
#include <nori/photonmap.h>
#include <nori/render.h>
#include <nori/sampler.h>
#include <nori/warp.h>

#include <tbb/task_arena.h>

#include <catch2/catch.hpp>

#include <chrono>

using namespace nori;
using namespace nori::testing;

namespace {

constexpr double kSignificance = 0.01;

std::shared_ptr<Emitter> loadEmitter(const std::string &xml, const std::string &directory = ".") {
    std::shared_ptr<NoriObject> root = loadFromXMLString(xml, directory);
    // An area light points at its shape: the pointer keeps the shape alive (aliasing).
    if (auto shape = std::dynamic_pointer_cast<Shape>(root))
        return std::shared_ptr<Emitter>(root, shape->getEmitterPtr().get());
    return std::dynamic_pointer_cast<Emitter>(root);
}

/// The mean photon weight (luminance) of n photons, t-tested against `power`.
StudentTResult photonPowerTest(const Emitter &emitter, double power, size_t n = 200000) {
    PCG32 random(7, 11);
    RunningMoments moments;
    for (size_t i = 0; i < n; ++i) {
        Ray3f ray;
        const Point2f position(random.nextFloat(), random.nextFloat());
        const Point2f direction(random.nextFloat(), random.nextFloat());
        const Color3f weight = emitter.samplePhoton(ray, position, direction);
        REQUIRE(weight.isValid());
        if (!(weight == 0.0f).all()) {
            REQUIRE(ray.o.allFinite());
            REQUIRE(std::abs(ray.d.norm() - 1.0f) < 1e-4f);
        }
        moments.add(weight.getLuminance());
    }
    return studentTTest(moments.mean, moments.variance(), moments.count, power, kSignificance);
}

/// The χ² test of photon directions against `pdf` (per solid angle).
ChiSquareResult photonDirectionTest(const Emitter &emitter,
                                    std::function<double(const Vector3f &)> pdf) {
    auto random = std::make_shared<PCG32>(3, 5); // positions: the test's own stream
    SamplingRoutine routine;
    routine.domain = SampleDomain::Sphere;
    routine.sample = [&emitter, random](const Point2f &sample, Vector3f &direction) {
        Ray3f ray;
        const Point2f position(random->nextFloat(), random->nextFloat());
        if ((emitter.samplePhoton(ray, position, sample) == 0.0f).all())
            return false;
        direction = ray.d;
        return true;
    };
    routine.pdf = std::move(pdf);
    ChiSquareOptions options;
    options.significanceLevel = kSignificance;
    options.seed = 17;
    return runChiSquareTest(routine, options).result;
}

const char *kQuadLight = R"(<mesh type="obj"><string name="filename" value="quad.obj"/>
    <emitter type="area"><color name="radiance" value="3, 2, 1"/></emitter></mesh>)";
/// A 1 × 0.5 quad facing −y.
const char *kQuadObj = "v -0.5 1 -0.25\nv 0.5 1 -0.25\nv 0.5 1 0.25\nv -0.5 1 0.25\n"
                       "vn 0 -1 0\nf 1//1 2//1 3//1 4//1\n";

/// The spot of the tests: along +x, cutoff 30°, full beam to 20°.
const char *kSpot = R"(<emitter type="spot"><point name="target" value="1, 0, 0"/>
    <color name="intensity" value="5, 4, 3"/>
    <float name="cutoffAngle" value="30"/> <float name="beamWidth" value="20"/></emitter>)";

double spotFalloff(double cosTheta) {
    const double cosBeam = std::cos(degToRad(20.0f)), cosCutoff = std::cos(degToRad(30.0f));
    const double t = std::clamp((cosTheta - cosCutoff) / (cosBeam - cosCutoff), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

/// A lat-long map with a bright patch and a gradient, for the envmap's photons.
std::string writeEnvironment(const TempDir &dir) {
    Bitmap map(Eigen::Vector2i(32, 16));
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x)
            map(y, x) = Color3f(0.2f + 0.05f * x, 0.5f, 0.1f + 0.1f * y);
    map(4, 9) = Color3f(40.0f, 30.0f, 20.0f);
    std::string path = (dir.path() / "sky.exr").string();
    map.saveEXR(path);
    return path;
}

} // namespace

TEST_CASE("Photons carry each light's power", "[photons][lights]") {
    TempDir dir;
    dir.write("quad.obj", kQuadObj);
    const std::string sky = writeEnvironment(dir);
    const std::vector<std::string> lights = {
        kQuadLight,
        R"(<mesh type="sphere"><float name="radius" value="0.5"/>
            <emitter type="area"><color name="radiance" value="2, 1, 1"/></emitter></mesh>)",
        R"(<emitter type="point"><point name="position" value="1, 2, 3"/>
            <color name="power" value="10, 20, 30"/></emitter>)",
        kSpot,
        R"(<emitter type="spot"><point name="target" value="1, 0, 0"/>
            <color name="intensity" value="5, 4, 3"/> <float name="cutoffAngle" value="30"/>
            <float name="beamWidth" value="10"/> <string name="falloff" value="linear"/></emitter>)",
        R"(<emitter type="directional"><vector name="direction" value="-1, -2, -0.5"/>
            <color name="irradiance" value="3, 2, 1"/></emitter>)",
        R"(<emitter type="constant"><color name="radiance" value="0.5, 1, 2"/></emitter>)",
        fmt::format(R"(<emitter type="envmap"><string name="filename" value="{}"/></emitter>)",
                    sky)};
    for (const std::string &xml : lights) {
        const std::shared_ptr<Emitter> emitter = loadEmitter(xml, dir.path().string());
        REQUIRE(emitter);
        CAPTURE(emitter->toString());
        const double power = emitter->getPower().getLuminance();
        const StudentTResult test = photonPowerTest(*emitter, power);
        INFO(test.message);
        CHECK(test.passed);
        // Negative control: the same photons against a power 2% off.
        CHECK_FALSE(photonPowerTest(*emitter, 1.02 * power).passed);
    }
}

TEST_CASE("Photon directions follow each light's emission distribution", "[photons][lights]") {
    TempDir dir;
    dir.write("quad.obj", kQuadObj);
    SECTION("area quad: cosine-weighted about its normal") {
        const auto emitter = loadEmitter(kQuadLight, dir.path().string());
        const auto cosine = [](const Vector3f &d) { return std::max(0.0, -double(d.y())) / kPi; };
        const ChiSquareResult result = photonDirectionTest(*emitter, cosine);
        INFO(result.message);
        CHECK(result.passed);
        // Negative control: uniform over the hemisphere.
        const auto uniform = [](const Vector3f &d) { return d.y() < 0.0f ? 0.5 / kPi : 0.0; };
        CHECK_FALSE(photonDirectionTest(*emitter, uniform).passed);
    }
    SECTION("area sphere, point and constant: uniform over the sphere") {
        for (const char *xml :
             {R"(<mesh type="sphere"><float name="radius" value="0.5"/>
                 <emitter type="area"><color name="radiance" value="1"/></emitter></mesh>)",
              R"(<emitter type="point"><color name="power" value="1"/></emitter>)",
              R"(<emitter type="constant"><color name="radiance" value="1"/></emitter>)"}) {
            const auto emitter = loadEmitter(xml);
            CAPTURE(emitter->toString());
            const ChiSquareResult result =
                photonDirectionTest(*emitter, [](const Vector3f &) { return 0.25 / kPi; });
            INFO(result.message);
            CHECK(result.passed);
        }
        // Negative control: the point light against a density leaning toward +z.
        const auto point =
            loadEmitter(R"(<emitter type="point"><color name="power" value="1"/></emitter>)");
        CHECK_FALSE(photonDirectionTest(*point, [](const Vector3f &d) {
                        return (1.0 + 0.1 * d.z()) * 0.25 / kPi;
                    }).passed);
    }
    SECTION("spot: its falloff within the cone") {
        const auto emitter = loadEmitter(kSpot);
        const double cosBeam = std::cos(degToRad(20.0f)), cosCutoff = std::cos(degToRad(30.0f));
        const double solidAngle = 2.0 * kPi * ((1.0 - cosBeam) + 0.5 * (cosBeam - cosCutoff));
        const auto falloff = [solidAngle](const Vector3f &d) {
            return spotFalloff(d.x()) / solidAngle;
        };
        const ChiSquareResult result = photonDirectionTest(*emitter, falloff);
        INFO(result.message);
        CHECK(result.passed);
        // Negative control: a falloff linear in cos θ across the ring.
        CHECK_FALSE(photonDirectionTest(*emitter, [=](const Vector3f &d) {
                        const double t =
                            std::clamp((d.x() - cosCutoff) / (cosBeam - cosCutoff), 0.0, 1.0);
                        return t / solidAngle;
                    }).passed);
    }
    SECTION("spot with Mitsuba's falloff, linear in the angle") {
        const auto emitter = loadEmitter(R"(<emitter type="spot">
            <point name="target" value="1, 0, 0"/> <color name="intensity" value="5, 4, 3"/>
            <float name="cutoffAngle" value="30"/> <float name="beamWidth" value="10"/>
            <string name="falloff" value="linear"/></emitter>)");
        const double beam = degToRad(10.0f), cutoff = degToRad(30.0f);
        // ∫ falloff dω = 2π [1 + (sin β − sin c)/(c − β)].
        const double solidAngle =
            2.0 * kPi * (1.0 + (std::sin(beam) - std::sin(cutoff)) / (cutoff - beam));
        const auto linear = [=](const Vector3f &d) {
            const double theta = std::acos(std::clamp(double(d.x()), -1.0, 1.0));
            return std::clamp((cutoff - theta) / (cutoff - beam), 0.0, 1.0) / solidAngle;
        };
        const ChiSquareResult result = photonDirectionTest(*emitter, linear);
        INFO(result.message);
        CHECK(result.passed);
        // Negative control: pbrt's smoothstep in cos θ over the same ring.
        const double cosBeam = std::cos(beam), cosCutoff = std::cos(cutoff);
        const double smoothAngle = 2.0 * kPi * ((1.0 - cosBeam) + 0.5 * (cosBeam - cosCutoff));
        CHECK_FALSE(photonDirectionTest(*emitter, [=](const Vector3f &d) {
                        const double t =
                            std::clamp((d.x() - cosCutoff) / (cosBeam - cosCutoff), 0.0, 1.0);
                        return t * t * (3.0 - 2.0 * t) / smoothAngle;
                    }).passed);
    }
    SECTION("envmap: its radiance's luminance, texel by texel") {
        const std::string sky = writeEnvironment(dir);
        const auto emitter = loadEmitter(fmt::format(
            R"(<emitter type="envmap"><string name="filename" value="{}"/></emitter>)", sky));
        // Texels are drawn ∝ luminance × sin θ of their row's centre and θ is uniform
        // within a texel, so the density is the emitter's pdf(): ∝ L up to a factor
        // sin θ_row/sin θ within each row, which the weights L/pdf undo (the power test).
        const auto density = [&](const Vector3f &d) {
            EmitterQueryRecord lRec;
            lRec.wi = -d;
            return emitter->pdf(lRec);
        };
        const ChiSquareResult result = photonDirectionTest(*emitter, density);
        INFO(result.message);
        CHECK(result.passed);
        // Negative control: uniform directions.
        CHECK_FALSE(
            photonDirectionTest(*emitter, [](const Vector3f &) { return 0.25 / kPi; }).passed);
    }
    SECTION("directional: one direction, origins uniform over the scene's disk") {
        const auto emitter = loadEmitter(R"(<emitter type="directional">
            <vector name="direction" value="-1, -2, -0.5"/></emitter>)");
        BoundingBox3f bounds(Point3f(-1.0f, 0.0f, -2.0f), Point3f(3.0f, 1.0f, 2.0f));
        emitter->setSceneBounds(bounds);
        SceneBoundingSphere sphere;
        sphere.set(bounds);
        const Vector3f toLight = Vector3f(1.0f, 2.0f, 0.5f).normalized();
        const Frame frame(toLight);
        auto test = [&](std::function<double(const Vector3f &)> pdf) {
            SamplingRoutine routine;
            routine.domain = SampleDomain::CenteredSquare;
            routine.sample = [&](const Point2f &sample, Vector3f &point) {
                Ray3f ray;
                emitter->samplePhoton(ray, sample, Point2f(0.5f, 0.5f));
                CHECK((ray.d + toLight).norm() < 1e-5f);
                // The origin, in units of the radius, on the disk facing the light.
                const Vector3f offset = (ray.o - sphere.center) / sphere.radius;
                CHECK(std::abs(offset.dot(toLight) - 1.0f) < 1e-4f);
                point = Vector3f(offset.dot(frame.s), offset.dot(frame.t), 0.0f);
                return true;
            };
            routine.pdf = std::move(pdf);
            ChiSquareOptions options;
            options.significanceLevel = kSignificance;
            return runChiSquareTest(routine, options).result;
        };
        const ChiSquareResult result =
            test([](const Vector3f &p) { return p.head<2>().norm() <= 1.0f ? kInvPi : 0.0; });
        INFO(result.message);
        CHECK(result.passed);
        // Negative control: a density growing toward the rim.
        CHECK_FALSE(test([](const Vector3f &p) {
                        const double r = p.head<2>().norm();
                        return r <= 1.0 ? (0.5 + r) * kInvPi / (0.5 + 2.0 / 3.0) : 0.0;
                    }).passed);
    }
}

TEST_CASE("The photon kd-tree finds exactly the photons within the radius", "[photons]") {
    PCG32 random(1, 2);
    std::vector<Photon> photons(20000);
    for (Photon &photon : photons) {
        // Clustered along a plane and in a blob, with duplicates: the hard cases.
        photon.position = Point3f(random.nextFloat(), 0.0f, random.nextFloat());
        if (random.nextFloat() < 0.3f)
            photon.position =
                Point3f(0.5f, 0.5f, 0.5f) +
                0.01f * Vector3f(random.nextFloat(), random.nextFloat(), random.nextFloat());
        photon.power = Color3f(random.nextFloat());
    }
    photons[5].position = photons[6].position;
    const PhotonMap map(photons);
    REQUIRE(map.size() == photons.size());
    for (int query = 0; query < 200; ++query) {
        const Point3f center(random.nextFloat(), query % 2 ? 0.0f : 0.5f, random.nextFloat());
        const float radius = 0.002f + 0.1f * random.nextFloat();
        size_t expected = 0;
        double expectedPower = 0.0;
        for (const Photon &photon : photons)
            if ((photon.position - center).squaredNorm() <= radius * radius) {
                ++expected;
                expectedPower += photon.power.r();
            }
        size_t found = 0;
        double foundPower = 0.0;
        map.forEachWithin(center, radius, [&](const Photon &photon) {
            ++found;
            foundPower += photon.power.r();
        });
        CHECK(found == expected);
        CHECK(foundPower == Approx(expectedPower).epsilon(1e-9).margin(1e-12));
    }
}

namespace {

/// A 20 × 20 diffuse floor (albedo ρ = 0.5) under a spherical light of radius 0.25 and
/// radiance 4 centred at height 1: by Lambert's formula for a sphere the floor's radiance
/// at horizontal distance d from below its centre is ρ·Le·R²·h/D³, D² = h² + d².
constexpr double kAlbedo = 0.5, kLe = 4.0, kLightRadius = 0.25, kHeight = 1.0;

/// A scene of `integrator` and `content` whose camera, at `origin` looking at `target`,
/// has one row of `width` pixels: the progressive photon mapper keeps its statistics per
/// pixel, and the tests give each query ray a pixel of its own.
std::shared_ptr<Scene> queryScene(const std::string &integrator, int width,
                                  const std::string &origin, const std::string &target,
                                  const std::string &content, const std::string &directory) {
    return loadScene(fmt::format(R"(<scene> {}
        <sampler type="independent"><integer name="sampleCount" value="1"/></sampler>
        <camera type="perspective"><integer name="width" value="{}"/><integer name="height" value="1"/>
            <transform name="toWorld"><lookat origin="{}" target="{}" up="0, 1, 0"/></transform>
        </camera> {} </scene>)",
                                 integrator, width, origin, target, content),
                     directory);
}

std::shared_ptr<Scene> planeUnderLight(const std::string &integrator, int width = 1) {
    return queryScene(integrator, width, "0, 3, 3", "0, 0, 0",
                      fmt::format(R"(<mesh type="obj"><string name="filename" value="floor.obj"/>
            <transform name="toWorld"><scale value="10"/></transform>
            <bsdf type="diffuse"><color name="albedo" value="{}"/></bsdf></mesh>
        <mesh type="sphere"><point name="center" value="0, {}, 0"/><float name="radius" value="{}"/>
            <bsdf type="diffuse"><color name="albedo" value="0"/></bsdf>
            <emitter type="area"><color name="radiance" value="{}"/></emitter></mesh>)",
                                  kAlbedo, kHeight, kLightRadius, kLe),
                      std::string(NORI_SOURCE_DIR) + "/scenes/textured/meshes");
}

double lambert(double d) {
    const double D = std::sqrt(kHeight * kHeight + d * d);
    return kAlbedo * kLe * kLightRadius * kLightRadius * kHeight / (D * D * D);
}

/// The mean of lambert over the disk of radius r about the origin: what a photon estimate
/// with radius r converges to (midpoint rule, 400 rings).
double lambertDiskMean(double r) {
    double sum = 0.0;
    const int rings = 400;
    for (int i = 0; i < rings; ++i) {
        const double rho = (i + 0.5) * r / rings;
        sum += lambert(rho) * 2.0 * rho * (r / rings);
    }
    return sum / (r * r);
}

/// A ray straight down onto the floor at (x, 0, z), from below the light.
Ray3f downAt(float x, float z) {
    return Ray3f(Point3f(x, 0.5f, z), Vector3f(0.0f, -1.0f, 0.0f));
}

} // namespace

TEST_CASE("A fixed photon radius blurs a plane's radiance by its stated bias, which shrinks "
          "with the radius",
          "[photons][integrators]") {
    // The estimate with radius r has the expectation lambertDiskMean(r) (every photon in
    // the disk counts); its bias against lambert(0) is at most r²/8·max|∇²L| (Taylor), here
    // ≈ 0.75·r²·L(0) since ∇²(h/D³) = −6/h⁴ at d = 0.
    auto scene = planeUnderLight(R"(<integrator type="photonmapper"/>)");
    const std::vector<float> radii = {0.2f, 0.1f, 0.05f};
    std::vector<RunningMoments> estimates(radii.size());
    std::unique_ptr<Sampler> sampler = scene->getSampler()->clone();
    for (uint64_t seed = 0; seed < 30; ++seed) {
        const PhotonMap map = tracePhotons(*scene, 100000, seed);
        for (size_t k = 0; k < radii.size(); ++k) {
            sampler->generate(Point2i(0, 0), 0);
            estimates[k].add(photonMappedRadiance(*scene, map, *sampler, downAt(0.0f, 0.0f),
                                                  radii[k], 0, nullptr)
                                 .getLuminance());
        }
    }
    for (size_t k = 0; k < radii.size(); ++k) {
        const double r = radii[k];
        const RunningMoments &m = estimates[k];
        const double standardError = std::sqrt(m.variance() / m.count);
        const double bias = lambertDiskMean(r) - lambert(0.0);
        const double biasBound = 0.75 * r * r * lambert(0.0) * 1.05; // 5% for O(r⁴)
        CAPTURE(r, m.mean, standardError, lambert(0.0), lambertDiskMean(r), bias, biasBound);
        REQUIRE(std::abs(bias) <= biasBound);
        // The estimate is unbiased for the disk mean...
        CHECK(
            studentTTest(m.mean, m.variance(), m.count, lambertDiskMean(r), kSignificance).passed);
        // ...so within the bias bound of Lambert's value, up to noise.
        CHECK(std::abs(m.mean - lambert(0.0)) <= biasBound + 3.0 * standardError);
    }
    // Negative control: at the largest radius the bias (3%) is plain to the t-test against
    // Lambert's value; at the smallest (0.2%) it is not.
    CHECK_FALSE(studentTTest(estimates[0].mean, estimates[0].variance(), estimates[0].count,
                             lambert(0.0), kSignificance)
                    .passed);
    CHECK(studentTTest(estimates[2].mean, estimates[2].variance(), estimates[2].count, lambert(0.0),
                       kSignificance)
              .passed);
}

namespace {

/// Runs `passes` passes of the scene's progressive photon mapper by hand at the query
/// rays (one pixel each, pixel i of row 0) and returns, per pass, the mean over the
/// queries of estimate / reference.
std::vector<double> progressivePassRatios(Scene &scene, const std::vector<Ray3f> &rays,
                                          const std::vector<double> &references, int passes) {
    Integrator *integrator = scene.getIntegrator();
    integrator->preprocess(&scene);
    std::unique_ptr<Sampler> sampler = scene.getSampler()->clone();
    std::vector<double> ratios;
    for (int pass = 0; pass < passes; ++pass) {
        const auto index = static_cast<uint32_t>(pass);
        integrator->beginPass(&scene, index, index + 1);
        double sum = 0.0;
        for (size_t i = 0; i < rays.size(); ++i) {
            sampler->generate(Point2i(static_cast<int>(i), 0), index);
            sum += integrator->Li(&scene, sampler.get(), rays[i]).getLuminance() / references[i];
        }
        integrator->endPass(&scene);
        ratios.push_back(sum / static_cast<double>(rays.size()));
    }
    return ratios;
}

StudentTResult tTestRatios(const std::vector<double> &ratios, double reference) {
    RunningMoments moments;
    for (double ratio : ratios)
        moments.add(ratio);
    return studentTTest(moments.mean, moments.variance(), moments.count, reference, kSignificance);
}

} // namespace

TEST_CASE("The progressive photon mapper converges to Lambert's formula on a plane",
          "[photons][integrators]") {
    // 25 query points 0.2 apart (farther than two radii, so nearly independent within a
    // pass); each pass gives one sample, the mean ratio to Lambert's value over them.
    std::vector<Ray3f> rays;
    std::vector<double> references;
    for (int i = -2; i <= 2; ++i)
        for (int j = -2; j <= 2; ++j) {
            rays.push_back(downAt(0.2f * i, 0.2f * j));
            references.push_back(lambert(0.2 * std::hypot(i, j)));
        }
    auto scene = planeUnderLight(R"(<integrator type="progressivephotonmapper">
        <integer name="photonCount" value="100000"/><float name="photonRadius" value="0.03"/>
        </integrator>)",
                                 static_cast<int>(rays.size()));
    const StudentTResult test =
        tTestRatios(progressivePassRatios(*scene, rays, references, 40), 1.0);
    INFO(test.message);
    CHECK(test.passed);

    // Negative control: a large radius that barely shrinks (α near 1) keeps its blur.
    auto biased = planeUnderLight(R"(<integrator type="progressivephotonmapper">
        <integer name="photonCount" value="100000"/><float name="photonRadius" value="0.3"/>
        <float name="alpha" value="0.999"/></integrator>)",
                                  static_cast<int>(rays.size()));
    const StudentTResult control =
        tTestRatios(progressivePassRatios(*biased, rays, references, 40), 1.0);
    INFO(control.message);
    CHECK_FALSE(control.passed);
}

namespace {

/// A closed 2 × 2 × 2 box whose six walls face inward, with `integrator`: every wall
/// emits radiance 1 and reflects diffusely with albedo a, so the radiance everywhere is
/// L = 1 + a·L = 1/(1 − a) (the white furnace).
std::shared_ptr<Scene> furnaceBox(const TempDir &dir, const std::string &integrator, float albedo,
                                  int width) {
    std::string obj;
    int vertex = 1;
    for (int axis = 0; axis < 3; ++axis)
        for (int sign : {-1, 1}) {
            // The wall at coordinate `sign` along `axis`, normal pointing inside.
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            for (auto [a, b] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
                int corner[3];
                corner[axis] = sign;
                corner[u] = a;
                corner[v] = b;
                obj += fmt::format("v {} {} {}\n", corner[0], corner[1], corner[2]);
            }
            int normal[3] = {0, 0, 0};
            normal[axis] = -sign;
            obj += fmt::format("vn {} {} {}\n", normal[0], normal[1], normal[2]);
            const int n = axis * 2 + (sign > 0) + 1;
            obj += fmt::format("f {0}//{4} {1}//{4} {2}//{4} {3}//{4}\n", vertex, vertex + 1,
                               vertex + 2, vertex + 3, n);
            vertex += 4;
        }
    dir.write("box.obj", obj);
    return queryScene(integrator, width, "0, 0, 0", "1, 0, 0",
                      fmt::format(R"(<mesh type="obj"><string name="filename" value="box.obj"/>
            <bsdf type="diffuse"><color name="albedo" value="{}"/></bsdf>
            <emitter type="area"><color name="radiance" value="1"/></emitter></mesh>)",
                                  albedo),
                      dir.path().string());
}

} // namespace

TEST_CASE("The progressive photon mapper passes the white furnace: 1/(1 − a)",
          "[photons][integrators]") {
    // Nine points 0.4 apart in the middle of the wall x = 1, at least 0.5 from its edges
    // (ten radii): there the photons within the radius all lie on that wall.
    std::vector<Ray3f> rays;
    for (int i = -1; i <= 1; ++i)
        for (int j = -1; j <= 1; ++j)
            rays.push_back(
                Ray3f(Point3f(0.0f, 0.0f, 0.0f), Vector3f(1.0f, 0.4f * i, 0.4f * j).normalized()));
    TempDir dir;
    const float albedo = 0.5f;
    auto scene = furnaceBox(dir, R"(<integrator type="progressivephotonmapper">
        <integer name="photonCount" value="50000"/><float name="photonRadius" value="0.05"/>
        </integrator>)",
                            albedo, static_cast<int>(rays.size()));
    const std::vector<double> references(rays.size(), 1.0 / (1.0 - albedo));
    const std::vector<double> ratios = progressivePassRatios(*scene, rays, references, 80);
    const StudentTResult test = tTestRatios(ratios, 1.0);
    INFO(test.message);
    CHECK(test.passed);
    // Negative control: the answer for albedo 0.52, 4% higher, is rejected.
    const StudentTResult control = tTestRatios(ratios, (1.0 - albedo) / (1.0 - 0.52));
    INFO(control.message);
    CHECK_FALSE(control.passed);
}

TEST_CASE("Photon mappers render the same image with one and two threads",
          "[photons][integrators]") {
    for (
        const char *integrator :
        {R"(<integrator type="photonmapper"><integer name="photonCount" value="20000"/></integrator>)",
         R"(<integrator type="progressivephotonmapper"><integer name="photonCount" value="20000"/></integrator>)"}) {
        CAPTURE(integrator);
        auto scene = loadScene(fmt::format(R"(<scene> {}
            <sampler type="independent"><integer name="sampleCount" value="4"/></sampler>
            <camera type="perspective"><integer name="width" value="24"/><integer name="height" value="24"/>
                <float name="fov" value="39"/>
                <transform name="toWorld"><lookat origin="0, 1, 3.85" target="0, 1, 0" up="0, 1, 0"/></transform>
            </camera>
            <mesh type="obj"><string name="filename" value="floor.obj"/></mesh>
            <mesh type="obj"><string name="filename" value="back.obj"/></mesh>
            <mesh type="obj"><string name="filename" value="light.obj"/>
                <emitter type="area"><color name="radiance" value="17, 12, 4"/></emitter></mesh>
            <mesh type="sphere"><point name="center" value="0.3, 0.35, 0.3"/>
                <float name="radius" value="0.35"/><bsdf type="dielectric"/></mesh>
            </scene>)",
                                           integrator),
                               std::string(NORI_SOURCE_DIR) + "/scenes/cbox/meshes");
        const RenderResult one = renderScene(*scene, quietOptions(1));
        const RenderResult two = renderScene(*scene, quietOptions(2));
        CHECK(identicalImages(one.image, two.image));
        float brightest = 0.0f;
        for (int y = 0; y < one.image.height(); ++y)
            for (int x = 0; x < one.image.width(); ++x)
                brightest = std::max(brightest, one.image(y, x).getLuminance());
        CHECK(brightest > 0.0f);
    }
}

TEST_CASE("The progressive photon mapper agrees with path_mis on a caustic, and at equal time "
          "it is the closer",
          "[photons][integrators]") {
    // A glass ball on a diffuse floor lit from the side by a small spherical light: the
    // camera looks down at the caustic beside the ball, where a path tracer finds the
    // light only by BSDF-sampled paths through the glass.
    const auto caustic = [](const std::string &integrator, int samples, int seed, float radiance) {
        return loadScene(fmt::format(R"(<scene> {}
            <sampler type="independent"><integer name="sampleCount" value="{}"/>
                <integer name="seed" value="{}"/></sampler>
            <camera type="perspective"><float name="fov" value="30"/>
                <integer name="width" value="32"/><integer name="height" value="32"/>
                <transform name="toWorld"><lookat origin="-0.65, 1.6, 0.001" target="-0.65, 0, 0" up="0, 0, -1"/></transform>
            </camera>
            <mesh type="obj"><string name="filename" value="floor.obj"/>
                <transform name="toWorld"><scale value="3"/></transform>
                <bsdf type="diffuse"><color name="albedo" value="0.8"/></bsdf></mesh>
            <mesh type="sphere"><point name="center" value="0, 0.3, 0"/><float name="radius" value="0.3"/>
                <bsdf type="dielectric"/></mesh>
            <mesh type="sphere"><point name="center" value="1.2, 0.9, 0"/><float name="radius" value="0.04"/>
                <bsdf type="diffuse"><color name="albedo" value="0"/></bsdf>
                <emitter type="area"><color name="radiance" value="{}"/></emitter></mesh>
            </scene>)",
                                     integrator, samples, seed, radiance),
                         std::string(NORI_SOURCE_DIR) + "/scenes/textured/meshes");
    };
    const std::string pathMis = R"(<integrator type="path_mis"/>)";
    const std::string progressive = R"(<integrator type="progressivephotonmapper">
        <integer name="photonCount" value="50000"/><float name="photonRadius" value="0.03"/>
        </integrator>)";
    // The caustic region: a fixed rectangle of pixels around the caustic, with a margin
    // of two pixels or more on every side where the floor is dark (< 0.02) in a long
    // photon-mapped render. Fixed, not chosen from the noisy images, whose noise would
    // then bias the region's mean.
    const ImageRegion region{"caustic", 8, 8, 24, 16};

    // The reference: path_mis at 16384 spp, its region mean's standard error from its
    // half-buffers, the pixels' correlation through the filter counted.
    RenderOptions referenceOptions = quietOptions(0);
    referenceOptions.aovs = {AOV::Variance};
    const RenderResult reference =
        renderScene(*caustic(pathMis, 16384, 1, 140.625f), referenceOptions);
    const RegionEstimate referenceMean = HalfBufferErrors(reference.layers).estimate(region)[0];
    const Bitmap referenceVariance = reference.layers.layer("variance");

    // Four renders each of the photon mapper and of path_mis, every one given the same
    // time (the photon mapper's first map, traced before the first pass, counted).
    constexpr double kSeconds = 1.5;
    constexpr int kRenders = 4;
    RenderOptions timed = quietOptions(0);
    timed.timeBudget = kSeconds;
    struct Renders {
        std::vector<double> means; ///< each render's region mean
        double squaredError = 0.0; ///< Σ over renders and pixels of (pixel − reference)²
        size_t passes = 0, samples = 0;
        double seconds = 0.0;
    };
    double referenceVarianceSum = 0.0; // Σ over the region's pixels of the reference's variance
    for (int y = region.y; y < region.y + region.height; ++y)
        for (int x = region.x; x < region.x + region.width; ++x)
            referenceVarianceSum += referenceVariance(y, x).r();
    const auto renderTimed = [&](const std::string &integrator, float radiance, int renders) {
        Renders out;
        for (int seed = 1; seed <= renders; ++seed) {
            const RenderResult render =
                renderScene(*caustic(integrator, 1 << 20, 100 + seed, radiance), timed);
            double sum = 0.0;
            for (int y = region.y; y < region.y + region.height; ++y)
                for (int x = region.x; x < region.x + region.width; ++x) {
                    sum += render.image(y, x).r();
                    out.squaredError +=
                        std::pow(render.image(y, x).r() - reference.image(y, x).r(), 2);
                }
            out.means.push_back(sum / (region.width * region.height));
            out.passes += render.passes;
            out.samples += render.samplesPerPixel;
            out.seconds += render.seconds;
        }
        return out;
    };
    const Renders photons = renderTimed(progressive, 140.625f, kRenders);
    const Renders paths = renderTimed(pathMis, 140.625f, kRenders);
    // RMSE over the region's pixels against the noisy reference, whose variance (the same
    // in both) is taken out: E[(a − ref)²] = E[(a − L)²] + Var ref.
    const double pixels = static_cast<double>(region.width * region.height) * kRenders;
    const auto rmse = [&](const Renders &r) {
        return std::sqrt(
            std::max(0.0, (r.squaredError - kRenders * referenceVarianceSum) / pixels));
    };
    RunningMoments photonMoments;
    for (double mean : photons.means)
        photonMoments.add(mean);
    const RegionEstimate photonMean{photonMoments.mean,
                                    std::sqrt(photonMoments.variance() / kRenders)};
    // The photon mapper's region mean against the reference's, in standard errors of both
    // (the photon mapper's from its four independent renders: one photon map per pass
    // correlates all its pixels, so its half-buffers would not do).
    const double combined = std::hypot(referenceMean.standardError, photonMean.standardError);
    const double z = (photonMean.mean - referenceMean.mean) / combined;
    CAPTURE(referenceMean.mean, referenceMean.standardError, photonMean.mean,
            photonMean.standardError, z, photons.passes, paths.samples, rmse(photons), rmse(paths));
    CHECK(std::abs(z) <= 4.0);
    // The smallest bias this sees with 95 % power: (4 + 1.645) standard errors.
    const double detectable = (4.0 + 1.645) * combined / referenceMean.mean;
    // At equal time the photon mapper is the closer of the two, pixel by pixel.
    CHECK(rmse(photons) < rmse(paths));
    // Negative control: a light 25 % brighter, one render, is told apart.
    const Renders brighter = renderTimed(progressive, 1.25f * 140.625f, 1);
    const double controlZ = (brighter.means[0] - referenceMean.mean) /
                            std::hypot(referenceMean.standardError,
                                       photonMean.standardError * std::sqrt(double(kRenders)));
    CAPTURE(controlZ);
    CHECK(std::abs(controlZ) > 4.0);
    WARN(fmt::format(
        "caustic: path_mis reference {:.4f} ± {:.4f} (16384 spp, {:.1f} s); in {} s each: "
        "progressive photon mapper {:.4f} ± {:.4f} ({:+.2f} SE; {:.1f} passes on average), RMSE "
        "{:.4f}; path_mis {:.0f} spp on average, RMSE {:.4f}; bias seen with 95 % power: {:.1f} %; "
        "a light 25 % brighter: {:+.1f} SE",
        referenceMean.mean, referenceMean.standardError, reference.seconds, kSeconds,
        photonMean.mean, photonMean.standardError, z, double(photons.passes) / kRenders,
        rmse(photons), double(paths.samples) / kRenders, rmse(paths), 100.0 * detectable,
        controlZ));
}

namespace {

/// Smooth glass whose lobe list gives each lobe the weight sample() returns for it,
/// forgetting to multiply it by the lobe's probability (a slip a student makes): sampled,
/// it is the real dielectric; split, it reflects 1/F times too much.
class GlassLobesWithoutProbability : public BSDF {
public:
    GlassLobesWithoutProbability() : m_glass(createDefault<BSDF>("dielectric")) {}
    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        return m_glass->sample(bRec, sample);
    }
    Color3f eval(const BSDFQueryRecord &bRec) const override { return m_glass->eval(bRec); }
    float pdf(const BSDFQueryRecord &bRec) const override { return m_glass->pdf(bRec); }
    int discreteLobes(const BSDFQueryRecord &bRec, DiscreteLobe *lobes) const override {
        const int count = m_glass->discreteLobes(bRec, lobes);
        for (int i = 0; i < count; ++i)
            lobes[i].weight /= lobes[i].probability; // the slip
        return count;
    }
    std::string toString() const override { return "GlassLobesWithoutProbability[]"; }

private:
    std::shared_ptr<BSDF> m_glass;
};

/// A glass ball on a diffuse floor beside a small spherical light, seen from the side so
/// that the light's reflection in the ball, the floor through it and its caustic are in
/// the 48 × 32 image; the ball's BSDF is `glass`.
std::shared_ptr<Scene> glassBallScene(const std::string &glass) {
    return loadScene(fmt::format(R"(<scene> <integrator type="photonmapper"/>
        <camera type="perspective"><float name="fov" value="35"/>
            <integer name="width" value="48"/><integer name="height" value="32"/>
            <transform name="toWorld"><lookat origin="-0.4, 0.9, -2.2" target="0, 0.25, 0" up="0, 1, 0"/></transform>
        </camera>
        <mesh type="obj"><string name="filename" value="floor.obj"/>
            <transform name="toWorld"><scale value="3"/></transform>
            <bsdf type="diffuse"><color name="albedo" value="0.8"/></bsdf></mesh>
        <mesh type="sphere"><point name="center" value="0, 0.3, 0"/><float name="radius" value="0.3"/>
            {}</mesh>
        <mesh type="sphere"><point name="center" value="0.8, 1.0, -0.6"/><float name="radius" value="0.06"/>
            <bsdf type="diffuse"><color name="albedo" value="0"/></bsdf>
            <emitter type="area"><color name="radiance" value="60"/></emitter></mesh>
        </scene>)",
                                 glass),
                     std::string(NORI_SOURCE_DIR) + "/scenes/textured/meshes");
}

/// Luminance moments of `count` photon-mapped camera samples at uniformly drawn image
/// positions, samples [firstSample, firstSample + count) of the scene's sampler.
RunningMoments photonMappedImageMean(const Scene &scene, const PhotonMap &map, int splitBounces,
                                     uint32_t firstSample, uint32_t count) {
    std::unique_ptr<Sampler> sampler = scene.getSampler()->clone();
    const Vector2i size = scene.getCamera()->getOutputSize();
    PCG32 positions(firstSample, 12);
    RunningMoments moments;
    for (uint32_t i = 0; i < count; ++i) {
        const Point2f position(positions.nextFloat() * size.x(), positions.nextFloat() * size.y());
        sampler->generate(position.cast<int>(), firstSample + i);
        Ray3f ray;
        const Color3f weight = scene.getCamera()->sampleRay(ray, position, sampler->next2D());
        const Color3f radiance =
            weight * photonMappedRadiance(scene, map, *sampler, ray, 0.03f, splitBounces, nullptr);
        moments.add(radiance.getLuminance());
    }
    return moments;
}

} // namespace

TEST_CASE("Camera paths that split at glass keep the image's mean and lose its speckles",
          "[photons][specular]") {
    // Following both of glass's lobes, each weighted by its probability, is the same
    // estimator in expectation as picking one by Fresnel: the image means of 200,000
    // samples each way, on one photon map, agree by Welch's t-test at 1 %. The light seen
    // reflected in the ball, found only by the few paths that pick reflection (F ≈ 4–10 %),
    // no longer makes the samples' variance: it must come out lower.
    constexpr uint32_t kSamples = 200000;
    auto scene = glassBallScene(R"(<bsdf type="dielectric"/>)");
    const PhotonMap map = tracePhotons(*scene, 50000, 5);
    const RunningMoments split = photonMappedImageMean(*scene, map, 3, 0, kSamples);
    const RunningMoments picked = photonMappedImageMean(*scene, map, 0, kSamples, kSamples);
    double t = 0.0;
    CHECK(samplesAgree(split, picked, t));
    CAPTURE(split.mean, picked.mean, t, split.variance(), picked.variance());
    CHECK(split.variance() < picked.variance());
    WARN(fmt::format("split at glass: mean {:.5f}, picked {:.5f} ({:+.2f} SE); per-sample "
                     "variance {:.4g} against {:.4g}",
                     split.mean, picked.mean, t, split.variance(), picked.variance()));

    // Negative control: glass whose lobes' weights lack their probabilities splits into
    // too bright an image, and the same test tells it apart. (A slip in the refraction's
    // (η_i/η_t)² would not do: in and out of a closed ball its factors cancel.)
    const TemporaryPlugin plugin(
        "glass_lobes_without_probability", NoriObject::EBSDF,
        [](const PropertyList &) { return std::make_shared<GlassLobesWithoutProbability>(); });
    auto slipped = glassBallScene(R"(<bsdf type="glass_lobes_without_probability"/>)");
    const PhotonMap slippedMap = tracePhotons(*slipped, 50000, 5);
    const RunningMoments wrong = photonMappedImageMean(*slipped, slippedMap, 3, 0, kSamples);
    double controlT = 0.0;
    CHECK_FALSE(samplesAgree(wrong, picked, controlT));
    WARN(fmt::format("negative control 'split glass, lobe weights without probabilities': "
                     "{:+.1f} SE",
                     controlT));
}
