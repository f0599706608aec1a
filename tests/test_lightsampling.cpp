// Triangle lights sampled in solid angle (sphericaltriangle.h, Mesh::sampleFromReference):
// directions uniform within the spherical triangles (χ², with a control that claims the
// area density and is rejected), the density 1/Ω the same for every point of the light,
// the area fallback where a triangle is nearly a point or seen edge-on, the light a close
// quad gives a floor against the closed form of its form factor, and the window room
// rendered with either sampling of its window.
#include "testing/agreement.h"
#include "testutil.h"

#include <nori/chisquare.h>
#include <nori/emitter.h>
#include <nori/mesh.h>
#include <nori/samplingroutines.h>
#include <nori/scene.h>
#include <nori/sphericaltriangle.h>
#include <nori/warp.h>

#include <catch2/catch.hpp>

using namespace nori;
using namespace nori::testing;

namespace {

/// A square of side 2 in the plane y = 0 (x, z in [-1, 1]), two triangles whose winding
/// faces −y (down), as an OBJ file.
const char *kSquareFacingDown = "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nf 1 2 3\nf 1 3 4\n";
/// One large triangle in the same plane, facing down.
const char *kTriangleFacingDown = "v -1 0 -1\nv 3 0 -1\nv -1 0 2\nf 1 2 3\n";

/// The area light of the only emitter of a scene made of the OBJ file `obj`.
struct LightFixture {
    TempDir dir;
    std::shared_ptr<Scene> scene;
    const Emitter *light = nullptr;
    const Shape *shape = nullptr;

    explicit LightFixture(const std::string &obj, const std::string &emitterExtra = "") {
        const std::string file = dir.write("light.obj", obj);
        scene = loadScene(fmt::format(R"(<scene><integrator type="direct_ems"/>
            <camera type="perspective"/>
            <mesh type="obj"><string name="filename" value="{}"/>
                <emitter type="area"><color name="radiance" value="1"/>{}</emitter></mesh>
            </scene>)",
                                      file, emitterExtra));
        light = scene->getEmitters().at(0).get();
        shape = light->getShape();
    }
};

} // namespace

TEST_CASE("A triangle's solid angle: an octant is π/2, a point in its plane sees none",
          "[lights][spherical]") {
    // The triangle (1,0,0), (0,1,0), (0,0,1) seen from the origin covers an octant.
    CHECK(sphericalTriangleSolidAngle(Point3f(1, 0, 0), Point3f(0, 1, 0), Point3f(0, 0, 1),
                                      Point3f(0, 0, 0)) == Approx(kPi / 2.0f).epsilon(1e-6));
    // Far away, Ω → A·cos θ/d²: a unit right triangle (area 1/2) 100 away, face on.
    CHECK(sphericalTriangleSolidAngle(Point3f(0, 0, 0), Point3f(1, 0, 0), Point3f(0, 1, 0),
                                      Point3f(0.3f, 0.3f, 100)) ==
          Approx(0.5 / 10000.0).epsilon(1e-3));
    CHECK(sphericalTriangleSolidAngle(Point3f(0, 0, 0), Point3f(1, 0, 0), Point3f(0, 1, 0),
                                      Point3f(5, 7, 0)) == 0.0f);
    const SphericalTriangle edgeOn(Vector3f(-5, -7, 0).normalized(),
                                   Vector3f(-4, -7, 0).normalized(),
                                   Vector3f(-5, -6, 0).normalized());
    CHECK_FALSE(sampleSphericalTriangle(edgeOn, Point2f(0.5f, 0.5f)));
}

TEST_CASE("Triangle lights seen up close are sampled uniformly in solid angle (chi-square)",
          "[lights][spherical][chi2]") {
    struct Case {
        const char *name;
        const char *obj;
        Point3f ref;
    };
    // Below the lights (their front side), from nearly a hemisphere to a small solid angle,
    // face on and at a slant.
    const std::vector<Case> cases = {
        {"square, 0.3 below its centre (4.6 sr)", kSquareFacingDown, Point3f(0, -0.3f, 0)},
        {"square, below a corner", kSquareFacingDown, Point3f(0.9f, -0.2f, 0.8f)},
        {"square, at a slant", kSquareFacingDown, Point3f(2, -1.5f, 0.5f)},
        {"large triangle, close", kTriangleFacingDown, Point3f(0, -0.4f, 0)},
    };
    ChiSquareOptions options;
    options.resolution = 20;
    options.sampleCount = 1000000;
    options.significanceLevel = sidakCorrection(0.01, static_cast<int>(cases.size()));
    for (const Case &c : cases) {
        CAPTURE(c.name);
        LightFixture fixture(c.obj);
        // The case is one for solid-angle sampling: the density is 1/Ω of the whole light.
        const auto &mesh = dynamic_cast<const Mesh &>(*fixture.shape);
        float total = 0.0f;
        for (const Vector3i &face : mesh.faces())
            total +=
                sphericalTriangleSolidAngle(mesh.positions()[face[0]], mesh.positions()[face[1]],
                                            mesh.positions()[face[2]], c.ref);
        CAPTURE(total);
        EmitterQueryRecord lRec(c.ref);
        REQUIRE((fixture.light->sample(lRec, Point2f(0.3f, 0.6f)) != 0.0f).any());
        CHECK(lRec.pdf == Approx(1.0f / total).epsilon(1e-5));
        CHECK(fixture.light->pdf(lRec) == Approx(1.0f / total).epsilon(1e-5));

        options.seed += 1;
        const ChiSquareReport report =
            runChiSquareTest(emitterRoutine(*fixture.light, c.ref), options);
        INFO(report.result.message);
        CHECK(report.result.passed);
    }

    // The control: Arvo's second step with its cos θ to b no longer uniform (the point
    // drawn by √u along the arc instead of u), which crowds the samples toward c′.
    LightFixture fixture(kSquareFacingDown);
    const Point3f ref(0.9f, -0.2f, 0.8f);
    const SamplingRoutine right = emitterRoutine(*fixture.light, ref);
    SamplingRoutine wrong = right;
    wrong.sample = [right](const Point2f &u, Vector3f &wi) {
        return right.sample(Point2f(u.x(), std::sqrt(u.y())), wi);
    };
    options.seed += 1;
    CHECK_FALSE(runChiSquareTest(wrong, options).result.passed);
}

namespace {

/// squareToBilinear with the weights `w`, against the density of the weights `claimed`.
SamplingRoutine bilinearRoutine(const std::array<float, 4> &w,
                                const std::array<float, 4> &claimed) {
    SamplingRoutine routine;
    routine.domain = SampleDomain::UnitSquare;
    routine.sample = [w](const Point2f &u, Vector3f &point) {
        const Point2f p = Warp::squareToBilinear(u, w);
        point = Vector3f(p.x(), p.y(), 0.0f);
        return true;
    };
    routine.pdf = [claimed](const Vector3f &point) {
        return Warp::squareToBilinearPdf(Point2f(point.x(), point.y()), claimed);
    };
    return routine;
}

} // namespace

TEST_CASE("The bilinear warp draws its density (chi-square)", "[lights][spherical][chi2]") {
    // Mild, steep (a floor of 0.01 against 1, as the cosine weights have), one-sided, and
    // all zero (uniform). The control (corners 10 % off) needs every sample: at a tenth of
    // them (the sanitizer runs' knob) it was no longer rejected.
    const FullTestSamples fullSamples;
    const std::vector<std::array<float, 4>> weights = {{0.2f, 1.0f, 0.5f, 3.0f},
                                                       {0.01f, 0.01f, 1.0f, 1.0f},
                                                       {1.0f, 0.01f, 1.0f, 0.01f},
                                                       {0.0f, 0.0f, 0.0f, 0.0f}};
    ChiSquareOptions options;
    options.resolution = 20;
    options.significanceLevel = sidakCorrection(0.01, static_cast<int>(weights.size()));
    for (const auto &w : weights) {
        CAPTURE(w[0], w[1], w[2], w[3]);
        options.seed += 1;
        const ChiSquareResult result = runChiSquareTest(bilinearRoutine(w, w), options).result;
        INFO(result.message);
        CHECK(result.passed);
    }
    // The control: samples of the mild weights against the density of weights 10 % steeper
    // in x.
    options.seed += 1;
    CHECK_FALSE(runChiSquareTest(bilinearRoutine(weights[0], {0.2f, 1.1f, 0.5f, 3.3f}), options)
                    .result.passed);
}

TEST_CASE("Inverting a spherical triangle's sample gives the sample back", "[lights][spherical]") {
    // Random triangles around the origin and random samples: the direction drawn from u,
    // inverted, is u again, to the precision of the float direction between them (the
    // trigonometry runs in double). Measured: 4.2e-4 at worst with GCC, 5.6e-5 with clang,
    // on slivers, whose vertices lie 135° to 160° apart; in float trigonometry it was
    // 6.3e-3 with GCC and 0.024 with clang, from the order of their sums. Triangles too small or too large for sampling
    // in solid angle are left out as the mesh leaves them.
    PCG32 random(21, 8);
    int triangles = 0;
    double worst = 0.0, controlWorst = 0.0;
    while (triangles < 300) {
        const SphericalTriangle triangle(randomDirection(random), randomDirection(random),
                                         randomDirection(random));
        if (!(triangle.solidAngle >= 0.05f &&
              triangle.solidAngle <= kMaxSphericalTriangleSolidAngle))
            continue;
        ++triangles;
        for (int i = 0; i < 20; ++i) {
            const Point2f u(0.02f + 0.96f * random.nextFloat(), 0.02f + 0.96f * random.nextFloat());
            const std::optional<Vector3f> w = sampleSphericalTriangle(triangle, u);
            REQUIRE(w);
            const std::optional<Point2f> back = invertSphericalTriangleSample(triangle, *w);
            REQUIRE(back);
            worst = std::max(worst, double((*back - u).cwiseAbs().maxCoeff()));
            const std::optional<Point2f> swapped = invertSphericalTriangleSample(
                SphericalTriangle(triangle.c, triangle.b, triangle.a), *w);
            REQUIRE(swapped);
            controlWorst = std::max(controlWorst, double((*swapped - u).cwiseAbs().maxCoeff()));
        }
    }
    CAPTURE(worst, controlWorst);
    CHECK(worst < 2e-3);
    // The control: inverting with a and c swapped (the other orientation of the square)
    // misses by far more.
    CHECK(controlWorst > 0.1);
    WARN("spherical triangle sample inverted: worst error " << worst << "; with a and c swapped "
                                                            << controlWorst);
}

TEST_CASE("Triangle lights seen up close are drawn by the cosine at the shading point "
          "(chi-square)",
          "[lights][spherical][chi2]") {
    // The square light from below, with the shading point's normal facing it, tilted, and
    // nearly in the light's plane: the warp's density, χ²-tested, and the density pdf()
    // gives at each sampled point equal to the one sample() returned.
    struct Case {
        const char *name;
        Point3f ref;
        Normal3f normal;
    };
    const std::vector<Case> cases = {
        {"below the centre, facing it", Point3f(0, -0.3f, 0), Normal3f(0, 1, 0)},
        {"below a corner, tilted", Point3f(0.9f, -0.2f, 0.8f), Normal3f(-0.6f, 0.8f, 0)},
        {"at a slant, nearly edge-on", Point3f(2, -1.5f, 0.5f), Normal3f(0.05f, 0.2f, 0.98f)},
    };
    ChiSquareOptions options;
    options.resolution = 20;
    options.sampleCount = 1000000;
    options.significanceLevel = sidakCorrection(0.01, static_cast<int>(cases.size()));
    options.seed = 40;
    LightFixture fixture(kSquareFacingDown);
    PCG32 random(3, 3);
    for (const Case &c : cases) {
        CAPTURE(c.name);
        const Normal3f normal = c.normal.normalized();
        double worst = 0.0;
        for (int i = 0; i < 2000; ++i) {
            EmitterQueryRecord lRec(c.ref);
            lRec.refNormal = normal;
            if ((fixture.light->sample(lRec, Point2f(random.nextFloat(), random.nextFloat())) ==
                 0.0f)
                    .all())
                continue;
            worst = std::max(worst, std::abs(fixture.light->pdf(lRec) / lRec.pdf - 1.0));
        }
        // Float spherical trigonometry, and the inversion's cut-off within 0.1° of a (where
        // it answers u = 0): measured 6.6e-4 at most.
        CAPTURE(worst);
        CHECK(worst < 2e-3);
        WARN(c.name << ": pdf() against sample()'s density, worst relative difference " << worst);
        options.seed += 1;
        const ChiSquareReport report =
            runChiSquareTest(emitterRoutine(*fixture.light, c.ref, normal), options);
        INFO(report.result.message);
        CHECK(report.result.passed);
    }
    // The control: the warped samples against the uniform density 1/Ω (the pdf told no
    // normal), which a light that forgot the warp in pdf() would claim.
    SamplingRoutine warped =
        emitterRoutine(*fixture.light, cases[1].ref, cases[1].normal.normalized());
    warped.pdf = emitterRoutine(*fixture.light, cases[1].ref).pdf;
    options.seed += 1;
    CHECK_FALSE(runChiSquareTest(warped, options).result.passed);
}

TEST_CASE("A triangle light far, nearly a point, or asked to, is sampled by area, consistently",
          "[lights][spherical]") {
    // 100 below, each triangle subtends 2·10⁻⁴ sr, under the bound of 3·10⁻⁴; 3 below,
    // beyond twice the light's bounding radius √2; 0.3 below, 2.3 sr, but the light asks
    // for area sampling.
    const std::vector<std::pair<Point3f, std::string>> cases = {
        {Point3f(0.2f, -100.0f, 0.1f), ""},
        {Point3f(0.0f, -3.0f, 0.0f), ""},
        {Point3f(0.0f, -0.3f, 0.0f), R"(<string name="sampling" value="area"/>)"}};
    for (const auto &[ref, extra] : cases) {
        CAPTURE(extra);
        LightFixture fixture(kSquareFacingDown, extra);
        EmitterQueryRecord lRec(ref);
        REQUIRE((fixture.light->sample(lRec, Point2f(0.3f, 0.6f)) != 0.0f).any());
        const float cosTheta = std::abs(lRec.n.dot(lRec.wi));
        const float areaDensity = (lRec.p - ref).squaredNorm() / (4.0f * cosTheta);
        CHECK(lRec.pdf == Approx(areaDensity).epsilon(1e-5));
        CHECK(fixture.light->pdf(lRec) == Approx(areaDensity).epsilon(1e-5));
    }
    CHECK_THAT(errorOf([] {
                   LightFixture(kSquareFacingDown, R"(<string name="sampling" value="cone"/>)");
               }),
               Catch::Contains("'sampling' is \"cone\""));
}

TEST_CASE("Points behind a one-sided light are known without sampling it", "[lights][spherical]") {
    // A flat square, a shallow roof of two triangles whose normals are 23° apart (a
    // cone of half-angle 11.3° about −y), and a tetrahedron (normals every way: never
    // behind, as far as the bound can tell).
    const char *roof = "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nv 0 -0.2 0\n"
                       "f 1 2 5\nf 3 4 5\n";
    const char *tetrahedron = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                              "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    PCG32 random(5, 7);
    for (const char *obj : {kSquareFacingDown, roof, tetrahedron}) {
        CAPTURE(obj);
        LightFixture fixture(obj);
        std::vector<ShapeSample> points;
        points.reserve(4000);
        for (int i = 0; i < 4000; ++i)
            points.push_back(
                fixture.shape->sampleSurface(Point2f(random.nextFloat(), random.nextFloat())));
        int behind = 0;
        for (int trial = 0; trial < 2000; ++trial) {
            const Point3f ref = randomPoint(random, 3.0f);
            CAPTURE(ref.transpose());
            if (!fixture.shape->facesAwayFrom(ref))
                continue;
            ++behind;
            // Every point of the light turns its emitting side away from ref, so the light
            // sends ref nothing, and its sample says so.
            for (const ShapeSample &point : points)
                REQUIRE(point.n.dot(ref - point.p) <= 0.0f);
            EmitterQueryRecord lRec(ref);
            CHECK((fixture.light->sample(lRec, Point2f(0.4f, 0.7f)) == 0.0f).all());
        }
        if (obj == tetrahedron)
            CHECK(behind == 0);
        else
            CHECK(behind > 300); // the square: half the cube; the roof: about a third
    }
    // Exactly in the square's plane, or just in front of it, is not behind.
    LightFixture square(kSquareFacingDown);
    CHECK_FALSE(square.shape->facesAwayFrom(Point3f(0.2f, 0.0f, 0.3f)));
    CHECK_FALSE(square.shape->facesAwayFrom(Point3f(3.0f, -1e-3f, 0.0f)));
    CHECK(square.shape->facesAwayFrom(Point3f(3.0f, 1e-3f, 0.0f)));
}

TEST_CASE("A floor under a close square light gets the light of its form factor",
          "[lights][spherical]") {
    // A square of side 2 at height h = 1/2 above a diffuse floor (albedo 1/2), facing it,
    // radiance 1. Below its centre, ∫cos θ dω is four corner rectangles of sides a = 1:
    // with X = a/h, each π·F = X/√(1 + X²) · atan(X/√(1 + X²)) (the differential-area to
    // parallel-rectangle form factor, Howell's catalogue, configuration B-3).
    const double x = 1.0 / 0.5, root = std::sqrt(1.0 + x * x);
    const double projectedSolidAngle = 4.0 * (x / root) * std::atan(x / root);
    const double reference = 0.5 / kPi * projectedSolidAngle;
    TempDir dir;
    const std::string light = dir.write("light.obj", kSquareFacingDown);
    for (const std::string integrator : {"direct_ems", "direct_mis"}) {
        CAPTURE(integrator);
        auto scene = loadScene(fmt::format(R"(<scene> <integrator type="{}"/>
            <sampler type="independent"><integer name="sampleCount" value="1"/></sampler>
            <camera type="perspective"><float name="fov" value="0.001"/>
                <integer name="width" value="1"/> <integer name="height" value="1"/>
                <transform name="toWorld"><lookat origin="0, 0.25, 0.6" target="0, 0, 0" up="0, 1, 0"/></transform>
            </camera>
            <mesh type="obj"><string name="filename" value="{}/scenes/textured/meshes/floor.obj"/>
                <transform name="toWorld"><scale value="1000"/></transform>
                <bsdf type="diffuse"><color name="albedo" value="0.5"/></bsdf></mesh>
            <mesh type="obj"><string name="filename" value="{}"/>
                <transform name="toWorld"><translate value="0, 0.5, 0"/></transform>
                <emitter type="area"><color name="radiance" value="1"/></emitter></mesh>
            </scene>)",
                                           integrator, NORI_SOURCE_DIR, light));
        const PixelTTest test = tTestPixel(*scene, reference, 20000);
        INFO(test.summary());
        CHECK(test.result.passed);
        // The control: the same estimate against a reference 2 % too large (what a light
        // sampled with its density 2 % too small gives) is rejected.
        CHECK_FALSE(studentTTest(test.moments.mean, test.moments.variance(), test.moments.count,
                                 1.02 * reference, 0.01)
                        .passed);
    }
}

namespace {

/// scenes/window/window.xml at 48 × 48 pixels, its window sampled by `sampling`, with the
/// radiance `radiance`.
AgreementScene windowRoom(const std::string &sampling, const std::string &radiance) {
    AgreementScene scene;
    scene.name = "window-" + sampling;
    scene.body = fmt::format(R"(
        <camera type="perspective"><float name="fov" value="70"/>
            <integer name="width" value="48"/> <integer name="height" value="48"/>
            <transform name="toWorld"><lookat origin="1.7, 1.4, 1.3" target="-1, 0.8, -1.4" up="0, 1, 0"/></transform>
        </camera>
        <mesh type="obj"><string name="filename" value="{0}/scenes/window/meshes/room.obj"/>
            <bsdf type="diffuse"><color name="albedo" value="0.7, 0.68, 0.64"/></bsdf></mesh>
        <mesh type="obj"><string name="filename" value="{0}/scenes/window/meshes/window.obj"/>
            <bsdf type="diffuse"><color name="albedo" value="0"/></bsdf>
            <emitter type="area"><color name="radiance" value="{1}"/>
                <string name="sampling" value="{2}"/></emitter></mesh>
        <mesh type="sphere"><point name="center" value="-1.3, 0.45, -1.2"/>
            <float name="radius" value="0.45"/>
            <bsdf type="diffuse"><color name="albedo" value="0.6, 0.25, 0.2"/></bsdf></mesh>)",
                             NORI_SOURCE_DIR, radiance, sampling);
    // The floor below the window, which sees it large and at grazing angles.
    scene.regions = {{"floor by the window", 0, 30, 20, 18}};
    Estimator pathMIS;
    pathMIS.label = "path_mis";
    pathMIS.integrator = R"(<integrator type="path_mis"/>)";
    pathMIS.samplesPerPixel = 64;
    scene.estimators = {pathMIS};
    return scene;
}

} // namespace

TEST_CASE("A window sampled in solid angle lights a room as one sampled by area",
          "[lights][spherical][agreement]") {
    // The control: a window 1 % brighter (more at reduced test counts, where at 1 % it was
    // only 2.4 standard errors off at a tenth), sampled in solid angle, disagrees.
    const double brighter = 1.0 + scaledPlantedBias(0.01);
    const std::string brighterRadiance =
        fmt::format("{}, {}, {}", 5.0 * brighter, 5.5 * brighter, 6.5 * brighter);
    const VariantAgreement result =
        compareVariant(windowRoom("area", "5, 5.5, 6.5"), windowRoom("solidangle", "5, 5.5, 6.5"),
                       windowRoom("solidangle", brighterRadiance), AgreementSettings());
    REQUIRE(result.variant.size() == 2);
    for (size_t region = 0; region < result.variant.size(); ++region) {
        CAPTURE(region);
        INFO("solid angle against area, " << result.summary(region));
        CHECK(result.variant[region].agrees);
        CHECK_FALSE(result.control[region].agrees);
    }
}
