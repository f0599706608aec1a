// Alpha masks (a shape's `alpha`, Mitsuba's `mask`): a quad between a floor and a light
// transmits the fraction of it that is absent, for every integrator, with no bias; two
// masks in a row transmit the product; the masked-out parts of a light do not shine.
#include "testutil.h"

#include <nori/parser.h>
#include <nori/pcg32.h>
#include <nori/scene.h>
#include <nori/shape.h>

#include <catch2/catch.hpp>

using namespace nori;
using namespace nori::testing;

namespace {

/// A black sphere light of radiance 100 and radius 0.1 at height 3 above litFloor's
/// target, and `occluders` between them.
std::string lightAbove(const std::string &occluders) {
    return R"(<mesh type="sphere"><point name="center" value="0, 3, 0"/>
        <float name="radius" value="0.1"/><bsdf type="diffuse"><color name="albedo" value="0"/></bsdf>
        <emitter type="area"><color name="radiance" value="100"/></emitter></mesh>)" +
           occluders;
}

/// A black horizontal square of side 0.8 at height y, facing down, with opacity `alpha`
/// (the XML of a float or of a texture named alpha): it covers the rays from the floor's
/// target to the light, not those of the camera (which pass above y = 1 at |z| ≥ 0.5).
std::string quadAt(float y, const std::string &alpha) {
    return fmt::format(R"(<mesh type="rectangle"><transform name="toWorld"><scale value="0.4"/>
        <rotate axis="1, 0, 0" angle="90"/><translate value="0, {}, 0"/></transform>{}
        <bsdf type="diffuse"><color name="albedo" value="0"/></bsdf></mesh>)",
                       y, alpha);
}

/// The floor's radiance with nothing in the way: ρ/π · E, E = π L (r/d)² for a sphere of
/// radius r seen straight up at distance d (its irradiance, PBR 4th ed. §4.5.1).
constexpr double kUnoccluded = 0.5 * 100.0 * (0.1 / 3.0) * (0.1 / 3.0);

const char *const kIntegrators[] = {"path_mis",   "path_ems", "path_mats",
                                    "direct_mis", "volpath",  "bdpt"};

} // namespace

TEST_CASE("A quad of opacity 0.35 transmits 65 % of the light, for every integrator",
          "[alpha][ttest]") {
    const std::string scene = lightAbove(quadAt(1.5f, R"(<float name="alpha" value="0.35"/>)"));
    for (const char *integrator : kIntegrators) {
        const auto test = tTestPixel(*litFloor(integrator, scene), 0.65 * kUnoccluded, 20000);
        INFO(integrator << ": " << test.summary());
        CHECK(test.result.passed);
    }
    // Negative controls: the quad opaque, or absent, is told apart.
    for (const char *alpha :
         {R"(<float name="alpha" value="1"/>)", R"(<float name="alpha" value="0"/>)"}) {
        const auto test = tTestPixel(*litFloor("path_mis", lightAbove(quadAt(1.5f, alpha))),
                                     0.65 * kUnoccluded, 20000);
        INFO(alpha << ": " << test.summary());
        CHECK_FALSE(test.result.passed);
    }
}

TEST_CASE("Two masks in a row transmit the product of what each lets through", "[alpha][ttest]") {
    // Each surface is decided on its own: a mask test shared along a ray (one random
    // number per ray, as a hash of the ray alone would give) would let 50 % through.
    // path_mats finds the small light by BSDF sampling alone, rarely: at a tenth of the
    // samples (the sanitizer runs' knob) none of its 2,000 found it (mean 0).
    const FullTestSamples fullSamples;
    const std::string scene = lightAbove(quadAt(1.2f, R"(<float name="alpha" value="0.5"/>)") +
                                         quadAt(1.8f, R"(<float name="alpha" value="0.5"/>)"));
    for (const char *integrator : {"path_mis", "path_mats", "bdpt"}) {
        const auto test = tTestPixel(*litFloor(integrator, scene), 0.25 * kUnoccluded, 20000);
        INFO(integrator << ": " << test.summary());
        CHECK(test.result.passed);
    }
    const auto correlated = tTestPixel(*litFloor("path_mis", scene), 0.5 * kUnoccluded, 20000);
    INFO("against 50 %: " << correlated.summary());
    CHECK_FALSE(correlated.result.passed);
}

TEST_CASE("A checkerboard cut-out casts a shadow of the mask's mean, through `mask` too",
          "[alpha][ttest]") {
    // Cells of 0.0016 (500 across the quad's uv): the rays from the floor point to the
    // light cross the quad over a disk of radius 0.05, some 3,000 cells, half of them holes.
    const std::string checker = R"(<texture type="checkerboard" name="alpha">
        <color name="color0" value="0"/><color name="color1" value="1"/>
        <float name="scale" value="500"/></texture>)";
    const std::string masked = lightAbove(quadAt(1.5f, checker));
    std::string viaMask = masked;
    viaMask.replace(viaMask.find(checker), checker.size(), "");
    const std::string maskBSDF = R"(<bsdf type="mask"><texture type="checkerboard" name="opacity">
        <color name="color0" value="0"/><color name="color1" value="1"/>
        <float name="scale" value="500"/></texture>
        <bsdf type="diffuse"><color name="albedo" value="0"/></bsdf></bsdf>)";
    const std::string blackBSDF =
        R"(<bsdf type="diffuse"><color name="albedo" value="0"/></bsdf></mesh>)";
    const size_t quad = viaMask.rfind(blackBSDF);
    REQUIRE(quad != std::string::npos);
    viaMask.replace(quad, blackBSDF.size(), maskBSDF + "</mesh>");
    for (const std::string &scene : {masked, viaMask})
        for (const char *integrator : {"path_mis", "path_mats", "bdpt"}) {
            const auto test = tTestPixel(*litFloor(integrator, scene), 0.5 * kUnoccluded, 20000);
            INFO(integrator << ": " << test.summary());
            CHECK(test.result.passed);
        }
}

TEST_CASE("The masked-out parts of a light do not shine, seen or sampled", "[alpha][ttest]") {
    // A light of opacity 0.4: the floor receives 40 % of what the whole light sends, by
    // light sampling (path_ems), by hitting it (path_mats) and by both.
    const std::string light = R"(<mesh type="sphere"><point name="center" value="0, 3, 0"/>
        <float name="radius" value="0.1"/><float name="alpha" value="0.4"/>
        <bsdf type="diffuse"><color name="albedo" value="0"/></bsdf>
        <emitter type="area"><color name="radiance" value="100"/></emitter></mesh>)";
    for (const char *integrator : {"path_mis", "path_ems", "path_mats"}) {
        const auto test = tTestPixel(*litFloor(integrator, light), 0.4 * kUnoccluded, 20000);
        INFO(integrator << ": " << test.summary());
        CHECK(test.result.passed);
    }
}

TEST_CASE("Alpha is checked: a number from 0 to 1 or a texture, not on a medium boundary",
          "[alpha][errors]") {
    CHECK_THAT(errorOf([] {
                   loadFromXMLString(
                       R"(<mesh type="cube"><float name="alpha" value="1.5"/></mesh>)");
               }),
               Catch::Contains("'alpha' must lie in [0, 1], got 1.5"));
    CHECK_THAT(errorOf([] {
                   loadFromXMLString(R"(<mesh type="cube"><float name="alpha" value="0.5"/>
                       <medium type="homogeneous" name="interior"/></mesh>)");
               }),
               Catch::Contains("alpha mask and bounds a medium"));
    const auto opaque = std::dynamic_pointer_cast<Shape>(
        loadFromXMLString(R"(<mesh type="cube"><float name="alpha" value="1"/></mesh>)"));
    REQUIRE(opaque);
    CHECK(opaque->getOpacity() == nullptr); // the fast path
}

TEST_CASE("A mask's test sees the position and uv that shading sees, bit for bit", "[alpha]") {
    // Shape::hitPoint is all a mask's test computes; a mesh overrides it with the same
    // interpolations as setHitInformation, which must give the same numbers (the mask's
    // stochastic choice hashes the point).
    TempDir dir;
    const std::string withUVs = dir.write("uv.obj", "v 0 0 0\nv 2 0.5 0\nv 0.3 1.7 -1\n"
                                                    "vt 0.1 0.2\nvt 0.9 0.3\nvt 0.4 0.95\n"
                                                    "f 1/1 2/2 3/3\n");
    const std::string withoutUVs = dir.write("plain.obj", "v 0 0 0\nv 2 0.5 0\nv 0.3 1.7 -1\n"
                                                          "f 1 2 3\n");
    for (const std::string &shapeXML :
         {fmt::format(R"(<mesh type="obj"><string name="filename" value="{}"/></mesh>)", withUVs),
          fmt::format(R"(<mesh type="obj"><string name="filename" value="{}"/></mesh>)",
                      withoutUVs),
          std::string(R"(<mesh type="sphere"><float name="radius" value="0.7"/></mesh>)")}) {
        INFO(shapeXML);
        const auto shape = std::dynamic_pointer_cast<Shape>(loadFromXMLString(shapeXML));
        REQUIRE(shape);
        PCG32 random(5, 11);
        for (int i = 0; i < 200; ++i) {
            // A ray from outside towards a random point of the shape.
            const ShapeSample sample =
                shape->sampleSurface(Point2f(random.nextFloat(), random.nextFloat()));
            const Point3f origin(3.0f, 2.0f, 4.0f);
            const Ray3f ray(origin, (sample.p - origin).normalized());
            float t;
            Point2f coords;
            if (!shape->rayIntersect(0, ray, t, coords))
                continue;
            Intersection its;
            its.t = t;
            shape->setHitInformation(0, ray, coords, its);
            Point3f p;
            Point2f uv;
            shape->hitPoint(0, ray, t, coords, p, uv);
            CHECK(p == its.p);
            CHECK(uv == its.uv);
        }
    }
}
