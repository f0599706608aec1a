// Spot and directional lights against closed forms: a diffuse point lit by them has
// radiance albedo/π · E · cos θ, E = I·falloff/d² (spot) or the given irradiance
// (directional). t-tests for the integrators that see delta lights, and the spot's power
// against the numerical integral of its intensity.
#include "testutil.h"

#include <nori/emitter.h>
#include <nori/parser.h>

#include <catch2/catch.hpp>

using namespace nori;
using namespace nori::testing;

namespace {

const char *kSpot = R"(<emitter type="spot"><point name="position" value="{}, 2, 0"/>
    <point name="target" value="{}, 0, 0"/> <color name="intensity" value="{}"/>
    <float name="cutoffAngle" value="30"/> <float name="beamWidth" value="20"/></emitter>)";

/// The radiance of the floor's origin under the spot at (x, 2, 0) aimed at (targetX, 0, 0).
/// With `smoothstep` false, the falloff in the ring is linear in cos θ instead (a control).
double spotReference(float x, float targetX, float intensity, bool smoothstep = true) {
    const Vector3f toOrigin = Vector3f(-x, -2.0f, 0.0f);
    const Vector3f axis = Vector3f(targetX - x, -2.0f, 0.0f).normalized();
    const float d2 = toOrigin.squaredNorm();
    const float cosAxis = axis.dot(toOrigin.normalized());
    const float cosBeam = std::cos(degToRad(20.0f)), cosCutoff = std::cos(degToRad(30.0f));
    const float t = std::clamp((cosAxis - cosCutoff) / (cosBeam - cosCutoff), 0.0f, 1.0f);
    const float falloff = smoothstep ? t * t * (3.0f - 2.0f * t) : t;
    const float cosSurface = 2.0f / std::sqrt(d2);
    return 0.5 * kInvPi * intensity * falloff / d2 * cosSurface;
}

/// The t-test, with a standard error of at most 0.75% of the reference: so a passing
/// estimate (|t| < 2.58 at α = 0.01) also lies within 2% of the reference.
void checkEstimate(Scene &scene, double reference, size_t samples = 2000) {
    const PixelTTest test = tTestPixel(scene, reference, samples);
    INFO(test.summary());
    CHECK(test.result.passed);
    const double standardError =
        std::sqrt(test.moments.variance() / static_cast<double>(test.moments.count));
    CHECK(standardError <= 0.0075 * reference + 1e-7);
}

const std::vector<std::string> kDeltaLightIntegrators = {"direct_ems", "direct_mis", "path_ems",
                                                         "path_mis", "whitted"};

} // namespace

TEST_CASE("A directional light gives a diffuse plane albedo/π · E · cos θ", "[lights]") {
    // Light travelling along (−1, −2, −0.5): cos θ = 2/|d| on the floor.
    const Vector3f direction(-1.0f, -2.0f, -0.5f);
    const double reference = 0.5 * kInvPi * 3.0 * (2.0 / direction.norm());
    const std::string light =
        R"(<emitter type="directional"><vector name="direction" value="-1, -2, -0.5"/>
        <color name="irradiance" value="3"/></emitter>)";
    for (const std::string &integrator : kDeltaLightIntegrators) {
        CAPTURE(integrator);
        checkEstimate(*litFloor(integrator, light), reference);
    }
    // The control: the same estimate against a reference 3% off is rejected.
    const RunningMoments moments = estimatePixel(*litFloor("direct_ems", light), 2000);
    CHECK_FALSE(
        studentTTest(moments.mean, moments.variance(), moments.count, 1.03 * reference, 0.01)
            .passed);
    // path_mats samples the BSDF only, and no ray ever hits a delta light.
    CHECK(estimatePixel(*litFloor("path_mats", light), 100).mean == 0.0);
    // A far occluder between the floor and the light: the shadow ray reaches past the scene.
    const std::string blocker = R"(<mesh type="obj"><string name="filename" value="floor.obj"/>
        <transform name="toWorld"><scale value="100"/><translate value="0, 50, 0"/></transform></mesh>)";
    CHECK(estimatePixel(*litFloor("direct_ems", light + blocker), 100).mean == 0.0);
}

TEST_CASE("A spot light: full inside the beam, smoothstep in the ring, dark outside", "[lights]") {
    // The spot at (x, 2, 0) aims at (targetX, 0, 0); the origin is seen at an angle from
    // its axis of 0° (inside the beam), ~25° (in the falloff ring) and ~35° (outside).
    for (const auto &[x, targetX] :
         {std::pair{1.0f, 0.0f}, std::pair{0.0f, 0.93f}, std::pair{0.0f, 1.4f}}) {
        CAPTURE(x, targetX);
        const double reference = spotReference(x, targetX, 40.0f);
        for (const std::string &integrator : kDeltaLightIntegrators) {
            CAPTURE(integrator);
            checkEstimate(*litFloor(integrator, fmt::format(kSpot, x, targetX, 40)), reference);
        }
    }
    CHECK(spotReference(0.0f, 1.4f, 40.0f) == 0.0);
    const double ring = spotReference(0.0f, 0.93f, 40.0f), full = spotReference(0.0f, 0.0f, 40.0f);
    CHECK((ring > 0.05 * full && ring < 0.95 * full)); // the case really is in the ring
    // The control: the same case against a linear falloff in the ring (not pbrt-v4's
    // smoothstep) is rejected.
    const PixelTTest wrong =
        tTestPixel(*litFloor("direct_ems", fmt::format(kSpot, 0.0f, 0.93f, 40)),
                   spotReference(0.0f, 0.93f, 40.0f, false), 2000);
    INFO(wrong.summary());
    CHECK_FALSE(wrong.result.passed);
}

TEST_CASE("Two lights of very unequal power add up for every integrator that sees them",
          "[lights]") {
    // The weak light's rare samples make the estimate normal only at the full count: at a
    // tenth (the sanitizer runs' knob) the t statistic of a correct integrator was 2.97.
    const FullTestSamples fullSamples;
    const std::string lights =
        fmt::format(kSpot, 1.0f, 0.0f, 2000) +
        R"(<emitter type="directional"><vector name="direction" value="0, -1, 0"/>
            <color name="irradiance" value="0.01"/></emitter>)";
    const double reference = spotReference(1.0f, 0.0f, 2000.0f) + 0.5 * kInvPi * 0.01;
    for (const std::string &integrator : kDeltaLightIntegrators) {
        CAPTURE(integrator);
        // The directional light has most of the power (over the huge floor) and a tiny
        // share of the radiance, so most light samples are spent on it: the variance is
        // about 1.6·10^5, and 10^6 samples bring the standard error to 0.7%.
        checkEstimate(*litFloor(integrator, lights), reference, 1000000);
    }
}

TEST_CASE("A spot light's power is the integral of its intensity over the sphere", "[lights]") {
    for (const auto &[cutoff, beam, falloff] :
         {std::tuple{30.0f, 20.0f, "smoothstep"}, std::tuple{60.0f, 0.0f, "smoothstep"},
          std::tuple{90.0f, 90.0f, "smoothstep"}, std::tuple{30.0f, 20.0f, "linear"},
          std::tuple{60.0f, 0.0f, "linear"}, std::tuple{90.0f, 90.0f, "linear"}}) {
        CAPTURE(cutoff, beam, falloff);
        auto spot = std::dynamic_pointer_cast<Emitter>(loadFromXMLString(fmt::format(
            R"(<emitter type="spot"><color name="intensity" value="3"/>
                <float name="cutoffAngle" value="{}"/> <float name="beamWidth" value="{}"/>
                <string name="falloff" value="{}"/></emitter>)",
            cutoff, beam, falloff)));
        REQUIRE(spot);
        // ∫ I(ω) dω by the midpoint rule in θ (the light is symmetric about its axis),
        // reading I(θ) from the light itself: the irradiance at distance 1.
        const int steps = 20000;
        double integral = 0.0;
        for (int i = 0; i < steps; ++i) {
            const double theta = (i + 0.5) * kPi / steps;
            EmitterQueryRecord lRec(Point3f(float(std::sin(theta)), 0.0f, float(std::cos(theta))));
            const double intensity = spot->sample(lRec, Point2f(0.5f, 0.5f)).r();
            integral += intensity * 2.0 * kPi * std::sin(theta) * (kPi / steps);
        }
        CHECK(spot->getPower().r() == Approx(integral).epsilon(1e-4));
    }
    // Given a power, the intensity follows: Φ = 3·(the solid angle) for the first light.
    auto byPower = std::dynamic_pointer_cast<Emitter>(
        loadFromXMLString(R"(<emitter type="spot"><color name="power" value="10"/></emitter>)"));
    CHECK(byPower->getPower().r() == Approx(10.0f));
}

TEST_CASE("Every light's shadowRay leaves the surface its reference point lies on", "[lights]") {
    // Course code tests scene->rayIntersect(lRec.shadowRay) from a hit point: a ray that
    // started on the surface at t = 0 would find it (a sphere's second root is ~1e-7
    // away) and leave curved objects black. From points of a unit sphere toward each
    // kind of light, nothing but the open sky lies in between.
    const std::vector<std::string> lights = {
        R"(<emitter type="point"><point name="position" value="0, 3, 0"/>
            <color name="intensity" value="1"/></emitter>)",
        fmt::format(kSpot, 0.0f, 0.0f, 10),
        R"(<emitter type="directional"><vector name="direction" value="0, -1, 0"/></emitter>)",
        R"(<emitter type="constant"/>)",
        R"(<mesh type="rectangle"><transform name="toWorld"><rotate axis="1, 0, 0" angle="90"/>
            <translate value="0, 3, 0"/></transform>
            <emitter type="area"><color name="radiance" value="1"/></emitter></mesh>)"};
    for (const std::string &light : lights) {
        CAPTURE(light);
        const auto scene = loadScene(
            R"(<scene><integrator type="path_mis"/>
               <camera type="perspective"><integer name="width" value="4"/>
               <integer name="height" value="4"/></camera>
               <mesh type="sphere"/>)" +
            light + "</scene>");
        const Emitter &emitter = *scene->getEmitters().front();
        PCG32 random(7, 1);
        int tested = 0;
        for (int i = 0; i < 400; ++i) {
            Vector3f n =
                Warp::squareToUniformSphere(Point2f(random.nextFloat(), random.nextFloat()));
            n.y() = std::abs(n.y());
            EmitterQueryRecord lRec{Point3f(n)};
            if ((emitter.sample(lRec, Point2f(random.nextFloat(), random.nextFloat())) == 0.0f)
                    .all() ||
                lRec.wi.dot(n) < 0.05f)
                continue;
            ++tested;
            INFO("ref " << n.transpose() << ", wi " << lRec.wi.transpose());
            CHECK(lRec.shadowRay.mint > 0.0f);
            CHECK_FALSE(scene->rayIntersect(lRec.shadowRay));
        }
        CHECK(tested > 50);
    }
}
