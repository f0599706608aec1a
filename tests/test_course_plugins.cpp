// Plugins of the newer course years' staff files: ETH 2024's `material` integrator and
// `uvtexture`, and ETH 2015's `distantdisk` light, against closed forms. (Their χ² tests
// run from their doc examples in autotest.sampling-plugins.)
#include <nori/parser.h>
#include <nori/texture.h>

#include "testutil.h"

#include <catch2/catch.hpp>

using namespace nori;
using nori::testing::litFloor;
using nori::testing::loadScene;
using nori::testing::tTestPixel;

namespace {

/// A light cap of half-angle thetaA (degrees) and radiance 2 centred on the floor's
/// normal (+y; the emitter's +z turned onto it).
std::string distantDisk(float thetaA) {
    return fmt::format(R"(<emitter type="distantdisk"><color name="radiance" value="2"/>
        <float name="thetaA" value="{}"/>
        <transform name="toWorld"><rotate axis="1, 0, 0" angle="-90"/></transform></emitter>)",
                       thetaA);
}

} // namespace

TEST_CASE("distantdisk lights a floor with the irradiance of its cap", "[course][lights]") {
    // A cap of half-angle α about the normal gives E = π L sin²α, so a diffuse floor of
    // albedo ρ reflects ρ L sin²α; α = 180° is a constant environment, ρ L.
    for (const float thetaA : {10.0f, 30.0f, 60.0f, 180.0f}) {
        const double sin2 = thetaA >= 90.0f ? 1.0 : std::pow(std::sin(degToRad(thetaA)), 2.0);
        const double reference = 0.5 * 2.0 * sin2;
        for (const std::string integrator : {"direct_ems", "direct_mats", "path_mis"}) {
            INFO(integrator << ", thetaA " << thetaA << ", reference " << reference);
            const auto test =
                tTestPixel(*litFloor(integrator, distantDisk(thetaA)), reference, 20000);
            INFO(test.summary());
            CHECK(test.result.passed);
        }
    }
    // Negative control: the same t-test rejects the reference of another cap.
    const auto wrong = tTestPixel(*litFloor("path_mis", distantDisk(30.0f)),
                                  0.5 * 2.0 * std::pow(std::sin(degToRad(33.0f)), 2.0), 20000);
    CHECK_FALSE(wrong.result.passed);
}

TEST_CASE("distantdisk of 180 degrees is the constant environment", "[course][lights]") {
    const auto disk = litFloor("path_mis", distantDisk(180.0f));
    const auto constant = litFloor(
        "path_mis", R"(<emitter type="constant"><color name="radiance" value="2"/></emitter>)");
    CHECK(disk->getEmitters().front()->getPower().isApprox(
        constant->getEmitters().front()->getPower(), 1e-5f));
}

TEST_CASE("material shows the BSDF value toward the normal", "[course][integrators]") {
    // The floor's diffuse albedo 0.5: f = 0.5/π whatever the viewing angle.
    const auto moments = nori::testing::estimatePixel(*litFloor("material", ""), 16);
    CHECK(moments.mean == Approx(0.5 / kPiDouble).epsilon(1e-6));
    CHECK(moments.variance() == Approx(0.0).margin(1e-12));
    // Where the ray escapes: black.
    const auto sky = loadScene(R"(<scene><integrator type="material"/>
        <camera type="perspective"><integer name="width" value="2"/><integer name="height" value="2"/></camera>
        </scene>)");
    CHECK(nori::testing::estimatePixel(*sky, 4).mean == 0.0);
}

TEST_CASE("uvtexture is ETH's ramp with its ripple", "[course][textures]") {
    const auto texture =
        std::dynamic_pointer_cast<Texture>(loadFromXMLString(R"(<texture type="uvtexture"/>)"));
    REQUIRE(texture);
    auto at = [&](float u, float v) { return texture->eval(TextureQuery(Point2f(u, v))); };
    // Where sin(16πu) or sin(16πv) vanishes the ripple is gone: (u, v, 0.5).
    CHECK(at(0.25f, 0.75f).isApprox(Color3f(0.25f, 0.75f, 0.5f), 1e-5f));
    // It wraps with |fmod(., 1)|: u = 1.25 is 0.25, v = −0.5 is 0.5.
    CHECK(at(1.25f, -0.5f).isApprox(Color3f(0.25f, 0.5f, 0.5f), 1e-4f));
    // At u = v = 1/32: sin(Cu) = sin(Cv) = 1 and cos(Cu) = 0, so r = u (1 − 0.2), g = v.
    CHECK(
        at(1.0f / 32.0f, 1.0f / 32.0f).isApprox(Color3f(0.8f / 32.0f, 1.0f / 32.0f, 0.5f), 1e-4f));
    CHECK(texture->average().isApprox(Color3f(0.5f)));
}
