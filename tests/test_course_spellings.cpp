// The spellings course scenes use for our plugins and parameters (environment, strength,
// sigma_a, lensRadius, the spot light's direction and cosines, henyey, irradiance): each
// reads as our own spelling, and a scene that gives both spellings is an error naming both.
#include <nori/common.h>
#include <nori/parser.h>

#include "testutil.h"

#include <catch2/catch.hpp>

using namespace nori;
using Catch::Contains;
using nori::testing::errorOf;

namespace {

std::string describe(const std::string &xml) {
    return loadFromXMLString(xml, NORI_SOURCE_DIR)->toString();
}

const std::string kSky = R"(<string name="filename" value="scenes/textured/textures/sky.exr"/>)";

} // namespace

TEST_CASE("envmap is also 'environment', and its 'strength' is 'scale'", "[spellings]") {
    const std::string ours = describe("<emitter type=\"envmap\">" + kSky +
                                      "<float name=\"scale\" value=\"2.5\"/></emitter>");
    const std::string course = describe("<emitter type=\"environment\">" + kSky +
                                        "<float name=\"strength\" value=\"2.5\"/></emitter>");
    CHECK_THAT(ours, Contains("scale=2.5"));
    CHECK(course == ours);
    CHECK_THAT(errorOf([] {
                   describe("<emitter type=\"envmap\">" + kSky +
                            "<float name=\"scale\" value=\"2\"/><float name=\"strength\" "
                            "value=\"2\"/></emitter>");
               }),
               Contains("'scale'") && Contains("'strength'") && Contains("two spellings"));
}

TEST_CASE("A homogeneous medium's sigma_a, sigma_s and sigma_t", "[spellings]") {
    CHECK(describe(R"(<medium type="homogeneous"><color name="sigma_s" value="0.5, 1, 2"/>
                          <color name="sigma_a" value="0.25"/></medium>)") ==
          describe(R"(<medium type="homogeneous"><color name="sigmaS" value="0.5, 1, 2"/>
                          <color name="sigmaA" value="0.25"/></medium>)"));
    CHECK(describe(R"(<medium type="homogeneous"><color name="sigma_t" value="3"/></medium>)") ==
          describe(R"(<medium type="homogeneous"><color name="sigmaT" value="3"/></medium>)"));
    CHECK_THAT(errorOf([] {
                   describe(R"(<medium type="homogeneous"><color name="sigmaA" value="1"/>
                                   <color name="sigma_a" value="1"/></medium>)");
               }),
               Contains("'sigmaA'") && Contains("'sigma_a'"));
}

TEST_CASE("The perspective camera's lensRadius is its apertureRadius", "[spellings]") {
    const std::string ours = describe(
        R"(<camera type="perspective"><float name="apertureRadius" value="0.125"/></camera>)");
    CHECK_THAT(ours, Contains("apertureRadius=0.125"));
    CHECK(describe(
              R"(<camera type="perspective"><float name="lensRadius" value="0.125"/></camera>)") ==
          ours);
    CHECK_THAT(errorOf([] {
                   describe(R"(<camera type="perspective"><float name="lensRadius" value="0.1"/>
                                   <float name="apertureRadius" value="0.1"/></camera>)");
               }),
               Contains("'apertureRadius'") && Contains("'lensRadius'"));
}

TEST_CASE("The spot light's direction, cosTotalWidth and cosFalloffStart", "[spellings]") {
    const std::string common =
        R"(<point name="position" value="0, 3, 0"/><color name="intensity" value="5"/>)";
    // The axis as a direction or as a target on it.
    CHECK(describe("<emitter type=\"spot\">" + common +
                   "<vector name=\"direction\" value=\"0, -2, 0\"/></emitter>") ==
          describe("<emitter type=\"spot\">" + common +
                   "<point name=\"target\" value=\"0, 0, 0\"/></emitter>"));
    // Cosines: the same float the angle makes of them.
    const std::string cutoff = fmt::format("{}", radToDeg(std::acos(0.5f)));
    const std::string beam = fmt::format("{}", radToDeg(std::acos(0.9f)));
    CHECK(describe("<emitter type=\"spot\">" + common +
                   "<float name=\"cosTotalWidth\" value=\"0.5\"/>"
                   "<float name=\"cosFalloffStart\" value=\"0.9\"/></emitter>") ==
          describe("<emitter type=\"spot\">" + common + "<float name=\"cutoffAngle\" value=\"" +
                   cutoff + "\"/><float name=\"beamWidth\" value=\"" + beam + "\"/></emitter>"));
    // A "cosine" above 1 is degrees, as several course scenes write it.
    CHECK(describe("<emitter type=\"spot\">" + common +
                   "<float name=\"cosTotalWidth\" value=\"40\"/>"
                   "<float name=\"cosFalloffStart\" value=\"25\"/></emitter>") ==
          describe("<emitter type=\"spot\">" + common +
                   "<float name=\"cutoffAngle\" value=\"40\"/><float name=\"beamWidth\" "
                   "value=\"25\"/></emitter>"));
    CHECK_THAT(errorOf([&] {
                   describe("<emitter type=\"spot\">" + common +
                            "<float name=\"cutoffAngle\" value=\"40\"/><float "
                            "name=\"cosTotalWidth\" value=\"0.5\"/></emitter>");
               }),
               Contains("'cutoffAngle'") && Contains("'cosTotalWidth'"));
    CHECK_THAT(errorOf([&] {
                   describe("<emitter type=\"spot\">" + common +
                            "<point name=\"target\" value=\"0, 0, 0\"/><vector name=\"direction\" "
                            "value=\"0, -1, 0\"/></emitter>");
               }),
               Contains("'target'") && Contains("'direction'"));
    CHECK_THAT(errorOf([&] {
                   describe("<emitter type=\"spot\">" + common +
                            "<float name=\"cosTotalWidth\" value=\"-2\"/></emitter>");
               }),
               Contains("must be a cosine"));
}

TEST_CASE("hg is also 'henyey' and 'henyeyGreenstein'", "[spellings]") {
    const std::string ours =
        describe(R"(<phase type="hg"><float name="g" value="0.625"/></phase>)");
    CHECK(describe(R"(<phase type="henyey"><float name="g" value="0.625"/></phase>)") == ours);
    CHECK(describe(R"(<phase type="henyeyGreenstein"><float name="g" value="0.625"/></phase>)") ==
          ours);
}

TEST_CASE("The directional light takes its irradiance", "[spellings]") {
    CHECK_THAT(describe(R"(<emitter type="directional"><color name="irradiance" value="3, 2, 1"/>
                           </emitter>)"),
               Contains("irradiance=(3, 2, 1)"));
}
