// The chi2test and ttest XML plugins and the warptest program, each with negative
// controls: a BSDF and an emitter whose pdf() does not match sample(), and wrong
// references.
#include <nori/bsdf.h>
#include <nori/chisquare.h>
#include <nori/emitter.h>
#include <nori/frame.h>
#include <nori/parser.h>
#include <nori/test.h>
#include <nori/warp.h>

#include "testutil.h"

#include <catch2/catch.hpp>

using namespace nori;
using Catch::Contains;
using nori::testing::errorOf;
using nori::testing::TempDir;

namespace {

/// Samples the uniform hemisphere but claims the cosine-weighted pdf (test-only plugin).
class MismatchedBSDF : public BSDF {
public:
    explicit MismatchedBSDF(const PropertyList &) {}
    Color3f sample(BSDFQueryRecord &bRec, const Point2f &u) const override {
        bRec.wo = Warp::squareToUniformHemisphere(u);
        bRec.measure = ESolidAngle;
        return Color3f(0.5f);
    }
    Color3f eval(const BSDFQueryRecord &) const override { return Color3f(0.5f * kInvPi); }
    float pdf(const BSDFQueryRecord &bRec) const override {
        return Warp::squareToCosineHemispherePdf(bRec.wo);
    }
    std::string toString() const override { return "MismatchedBSDF[]"; }
};
NORI_REGISTER_CLASS(MismatchedBSDF, "test_mismatched");

/// A light filling the cone of directions within `angle` of +z, seen the same from every
/// point (like a distant disk); `pdfScale` ≠ 1 makes its pdf wrong (test-only plugin).
class ConeEmitter : public Emitter {
public:
    explicit ConeEmitter(const PropertyList &props)
        : m_cosThetaMax(std::cos(degToRad(props.getFloat("angle", 20.0f)))),
          m_pdfScale(props.getFloat("pdfScale", 1.0f)) {}
    Color3f sample(EmitterQueryRecord &lRec, const Point2f &u) const override {
        lRec.wi = Warp::squareToUniformSphereCap(u, m_cosThetaMax);
        lRec.pdf = pdf(lRec);
        return Color3f(1.0f / lRec.pdf);
    }
    Color3f eval(const EmitterQueryRecord &) const override { return Color3f(1.0f); }
    Color3f getPower() const override { return Color3f(1.0f); }
    float pdf(const EmitterQueryRecord &lRec) const override {
        return m_pdfScale * Warp::squareToUniformSphereCapPdf(lRec.wi, m_cosThetaMax);
    }
    std::string toString() const override { return "ConeEmitter[]"; }

private:
    float m_cosThetaMax, m_pdfScale;
};
NORI_REGISTER_CLASS(ConeEmitter, "test_cone");

bool runTest(const std::string &xml) {
    auto test = std::dynamic_pointer_cast<Test>(loadFromXMLString(xml));
    REQUIRE(test);
    return test->run();
}

} // namespace

TEST_CASE("chi2test accepts correct samplers of every kind", "[chi2test]") {
    CHECK(runTest(R"(<test type="chi2test">
        <integer name="testCount" value="2"/>
        <integer name="sampleCount" value="200000"/>
        <bsdf type="diffuse"/>
        <phase type="hg"><float name="g" value="0.6"/></phase>
        <emitter type="test_cone"/>
    </test>)"));
}

TEST_CASE("chi2test rejects a BSDF and an emitter whose pdf does not match (negative "
          "controls)",
          "[chi2test][negative]") {
    CHECK_FALSE(runTest(R"(<test type="chi2test">
        <integer name="sampleCount" value="200000"/><bsdf type="test_mismatched"/></test>)"));
    CHECK_FALSE(runTest(R"(<test type="chi2test">
        <integer name="sampleCount" value="200000"/>
        <emitter type="test_cone"><float name="pdfScale" value="0.97"/></emitter></test>)"));
}

TEST_CASE("chi2test draws the picture of every failing case, named after plugin, parameters "
          "and angle",
          "[chi2test]") {
    TempDir dir;
    TestOptions options;
    options.pictureFolder = dir.path().string();
    auto count = [&] {
        return std::distance(std::filesystem::directory_iterator(dir.path()),
                             std::filesystem::directory_iterator());
    };
    auto run = [&](const std::string &xml) {
        auto test = std::dynamic_pointer_cast<Test>(loadFromXMLString(xml));
        REQUIRE(test);
        return test->run(options);
    };
    const std::string passing = R"(<test type="chi2test"><integer name="testCount" value="2"/>
        <integer name="sampleCount" value="100000"/><bsdf type="diffuse"/></test>)";
    CHECK(run(passing));
    CHECK(count() == 0); // nothing failed, nothing drawn
    CHECK_FALSE(run(R"(<test type="chi2test"><integer name="testCount" value="3"/>
        <integer name="sampleCount" value="100000"/><bsdf type="test_mismatched"/></test>)"));
    CHECK(count() == 3);
    for (const auto &entry : std::filesystem::directory_iterator(dir.path()))
        CHECK_THAT(entry.path().filename().string(),
                   Catch::Matches("test_mismatched_wi-[0-9.]+deg-phi--?[0-9]+deg\\.png"));
    options.allPictures = true;
    CHECK(run(passing));
    CHECK(count() == 5); // and with the flag, the passing cases too
    bool diffuseDrawn = false;
    for (const auto &entry : std::filesystem::directory_iterator(dir.path()))
        diffuseDrawn |=
            entry.path().filename().string().rfind("diffuse_albedo=0.5,0.5,0.5_wi-", 0) == 0;
    CHECK(diffuseDrawn);
}

TEST_CASE("ttest indexes references BSDF by BSDF (Nori 2's bug fixed)", "[ttest]") {
    const std::string bsdfs = R"(<string name="angles" value="0, 60"/>
        <integer name="sampleCount" value="1000"/>
        <bsdf type="diffuse"><color name="albedo" value="0.3"/></bsdf>
        <bsdf type="diffuse"><color name="albedo" value="0.7"/></bsdf>)";
    CHECK(runTest(R"(<test type="ttest"><string name="references" value="0.3, 0.3, 0.7, 0.7"/>)" +
                  bsdfs + "</test>"));
    // Negative control: references in the order Nori 2 would read them.
    CHECK_FALSE(
        runTest(R"(<test type="ttest"><string name="references" value="0.3, 0.7, 0.3, 0.7"/>)" +
                bsdfs + "</test>"));
}

TEST_CASE("ttest reports a mismatch between references and tests", "[ttest]") {
    CHECK_THAT(errorOf([] {
                   loadFromXMLString(R"(<test type="ttest"><string name="angles" value="0, 30"/>
                       <string name="references" value="0.5"/><bsdf type="diffuse"/></test>)");
               }),
               Contains("1 references given, 2 expected"));
    CHECK_THAT(errorOf([] { loadFromXMLString(R"(<test type="ttest"/>)"); }),
               Contains("nothing to test"));
}

TEST_CASE("warptest writes the picture and exits with the verdict", "[warptest]") {
    TempDir dir;
    auto run = [&](std::vector<std::string> arguments) {
        arguments.insert(arguments.begin(), WARPTEST_EXECUTABLE);
        arguments.push_back("--out");
        arguments.push_back(dir.path().string());
        std::string command;
        for (const std::string &argument : arguments)
            command += "'" + argument + "' ";
        return std::system((command + "> /dev/null 2>&1").c_str());
    };
    CHECK(run({"cosine_hemisphere"}) == 0);
    CHECK(std::filesystem::exists(dir.path() / "warptest-cosine_hemisphere.png"));
    CHECK(run({"ggx", "--param", "0.2"}) == 0);
    CHECK(std::filesystem::exists(dir.path() / "warptest-ggx_alpha=0.2.png"));
    // Pictures are named after what was tested and the angle: runs do not overwrite.
    CHECK(run({"bsdf", "<bsdf type=\"diffuse\"/>", "--angle", "70"}) == 0);
    CHECK(run({"bsdf", "<bsdf type=\"diffuse\"/>", "--angle", "30"}) == 0);
    CHECK(
        std::filesystem::exists(dir.path() / "warptest-bsdf-diffuse_albedo=0.5,0.5,0.5_70deg.png"));
    CHECK(
        std::filesystem::exists(dir.path() / "warptest-bsdf-diffuse_albedo=0.5,0.5,0.5_30deg.png"));
    CHECK(run({"phase", "<phase type=\"hg\"><float name=\"g\" value=\"-0.3\"/></phase>"}) == 0);
    CHECK(std::filesystem::exists(dir.path() / "warptest-phase-hg_g=-0.3_30deg.png"));
    CHECK(WEXITSTATUS(run({"cosine_hemispher"})) == 2); // a typo is an error, not a verdict
}

TEST_CASE("Picture names keep minus signs for negative values only", "[chi2][pictures]") {
    CHECK(chiSquarePictureName("plastic", "kd=[0.5, 0.5, 0.5], alpha=-0.1", "wi-30deg") ==
          "plastic_kd=0.5,0.5,0.5,alpha=-0.1_wi-30deg");
    CHECK(chiSquarePictureName("bsdf-diffuse", "albedo=[0.5, 0.5, 0.5]", "") ==
          "bsdf-diffuse_albedo=0.5,0.5,0.5");
    CHECK(chiSquarePictureName("x", " (a) ", "[b]") == "x_a_b");
}
