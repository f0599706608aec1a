// The Mitsuba importer (mitsubaimport.h): both dialects rendering bit for bit as our
// hand-written XML, the conversions where Mitsuba's definitions differ from ours (fovAxis,
// focalLength, sRGB, spectra, depths) against their closed forms, and its errors.
#include <nori/imagefile.h>
#include <nori/mitsubaimport.h>

#include "testutil.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>

using namespace nori;
using namespace nori::testing;
using Catch::Contains;
namespace fs = std::filesystem;

namespace {

constexpr double kMitsubaTestPi = 3.14159265358979323846;

/// A Mitsuba scene around `body`: a 200 × 100 film, our defaults otherwise.
std::string mitsubaScene(const std::string &body, const std::string &sensor = "",
                         const std::string &version = "0.6.0") {
    return fmt::format(R"(<scene version="{}">
    <sensor type="perspective">
        {}
        <film type="hdrfilm">
            <integer name="width" value="200"/><integer name="height" value="100"/>
        </film>
    </sensor>
    {}
</scene>)",
                       version, sensor.empty() ? R"(<float name="fov" value="40"/>)" : sensor,
                       body);
}

mitsuba::Conversion importMitsuba(const std::string &text,
                                  const std::map<std::string, std::string> &defines = {}) {
    mitsuba::ConvertOptions options;
    options.defines = defines;
    return mitsuba::convertText(text, "test.xml", options);
}

/// The number after `name="NAME" value="` in the XML (its first one, of a list).
double mitsubaNumber(const std::string &xml, const std::string &name) {
    const std::string key = "name=\"" + name + "\" value=\"";
    const size_t at = xml.find(key);
    REQUIRE(at != std::string::npos);
    return std::stod(xml.substr(at + key.size()));
}

/// The three numbers after `name="NAME" value="`.
Color3f mitsubaColor(const std::string &xml, const std::string &name) {
    const std::string key = "name=\"" + name + "\" value=\"";
    const size_t at = xml.find(key);
    REQUIRE(at != std::string::npos);
    float r = 0, g = 0, b = 0;
    REQUIRE(std::sscanf(xml.c_str() + at + key.size(), "%f, %f, %f", &r, &g, &b) == 3);
    return Color3f(r, g, b);
}

double degrees(double radians) {
    return radians * 180.0 / kMitsubaTestPi;
}
double radians(double degrees) {
    return degrees * kMitsubaTestPi / 180.0;
}

} // namespace

TEST_CASE("Mitsuba 0.6 and 3 scenes render bit for bit as our hand-written XML",
          "[mitsuba][import][cli]") {
    const fs::path data = fs::path(NORI_SOURCE_DIR) / "tests/data/mitsuba";
    const TempDir dir;
    // scene-*: shapes, BSDFs, lights, variables, an include; more-*: instances, media,
    // a thin lens, a bitmap on a serialized mesh, other samplers, films and integrators;
    // extra-*: bump and normal maps, an envmap, a spot, a low-discrepancy sampler;
    // grid-*: the gridvolume, which the two versions define differently, and principled.
    const std::vector<std::pair<std::string, std::vector<std::string>>> groups = {
        {"scene-ours.xml", {"scene-0.6.xml", "scene-3.xml"}},
        {"more-ours.xml", {"more-0.6.xml", "more-3.xml"}},
        {"extra-ours.xml", {"extra-0.6.xml", "extra-3.xml"}},
        {"grid-0.6-ours.xml", {"grid-0.6.xml"}},
        {"grid-3-ours.xml", {"grid-3.xml"}}};
    std::vector<Bitmap> images;
    for (const auto &[ours, mitsubaFiles] : groups) {
        std::vector<Bitmap> group;
        std::vector<std::string> scenes = {ours};
        scenes.insert(scenes.end(), mitsubaFiles.begin(), mitsubaFiles.end());
        for (const std::string &scene : scenes) {
            const std::string output = (dir.path() / fs::path(scene).stem()).string();
            const ProcessResult result =
                runNori({(data / scene).string(), "--no-progress", "-o", output});
            INFO(scene << ": " << result.output);
            REQUIRE(result.exitCode == 0);
            // Every mapping of these scenes is exact: no stand-in, no warning.
            CHECK_THAT(result.output, !Contains("Warning"));
            group.push_back(readImageFile(output + ".exr").pixels);
        }
        for (size_t i = 1; i < group.size(); ++i) {
            INFO(scenes[i] << " against " << ours);
            CHECK(identicalImages(group[0], group[i]));
        }
        images.push_back(group[0]);
    }

    // `nori convert` writes XML that renders the same image, from another folder.
    for (size_t g = 0; g < groups.size(); ++g)
        for (const std::string &scene : groups[g].second) {
            const std::string stem = fs::path(scene).stem().string();
            const std::string xml = (dir.path() / "out" / (stem + ".xml")).string();
            const ProcessResult converted =
                runNori({"convert", (data / scene).string(), "-o", xml});
            INFO(scene << ": " << converted.output);
            REQUIRE(converted.exitCode == 0);
            const ProcessResult rendered = runNori({xml, "--no-progress"});
            INFO(rendered.output);
            REQUIRE(rendered.exitCode == 0);
            CHECK(identicalImages(
                images[g], readImageFile((dir.path() / "out" / (stem + ".exr")).string()).pixels));
        }
}

TEST_CASE("A Mitsuba file is told from ours by its <scene version>", "[mitsuba][import]") {
    const TempDir dir;
    CHECK(mitsuba::isMitsubaFile(dir.write("m.xml", mitsubaScene(""))));
    CHECK_FALSE(mitsuba::isMitsubaFile(dir.write("ours.xml", "<scene>\n</scene>\n")));
    CHECK_FALSE(mitsuba::isMitsubaFile((dir.path() / "missing.xml").string()));
}

TEST_CASE("Mitsuba's fovAxis and focalLength become our horizontal fov", "[mitsuba][import]") {
    // The film is 200 × 100 (aspect 2).
    const auto fovOf = [](const std::string &sensor) {
        return mitsubaNumber(importMitsuba(mitsubaScene("", sensor)).xml, "fov");
    };
    const double half = radians(20.0);
    CHECK(fovOf(R"(<float name="fov" value="40"/>)") == Approx(40.0).epsilon(1e-6));
    const double fromY = degrees(2.0 * std::atan(std::tan(half) * 2.0));
    CHECK(fovOf(R"(<float name="fov" value="40"/><string name="fovAxis" value="y"/>)") ==
          Approx(fromY).epsilon(1e-5));
    // The smaller axis of a wide film is y, the larger x.
    CHECK(fovOf(R"(<float name="fov" value="40"/><string name="fovAxis" value="smaller"/>)") ==
          Approx(fromY).epsilon(1e-5));
    CHECK(fovOf(R"(<float name="fov" value="40"/><string name="fovAxis" value="larger"/>)") ==
          Approx(40.0).epsilon(1e-6));
    // The diagonal spans tan(20°) across sqrt(1 + 1/4) of the width's half.
    const double fromDiagonal =
        degrees(2.0 * std::atan(std::tan(half) / std::sqrt(1.0 + 1.0 / 4.0)));
    CHECK(fovOf(R"(<float name="fov" value="40"/><string name="fovAxis" value="diagonal"/>)") ==
          Approx(fromDiagonal).epsilon(1e-5));
    // 35 mm film: a diagonal of sqrt(36² + 24²) = 43.27 mm over the focal length.
    const double diagonal = std::sqrt(36.0 * 36.0 + 24.0 * 24.0);
    const double fromFocal =
        degrees(2.0 * std::atan(diagonal / (2.0 * 28.0) / std::sqrt(1.0 + 1.0 / 4.0)));
    CHECK(fovOf(R"(<string name="focalLength" value="28mm"/>)") == Approx(fromFocal).epsilon(1e-5));
    CHECK(fovOf("<float name=\"nearClip\" value=\"0.1\"/>") ==
          Approx(degrees(2.0 * std::atan(diagonal / 100.0 / std::sqrt(1.25)))).epsilon(1e-5));
    CHECK_THAT(errorOf([] {
                   importMitsuba(mitsubaScene(
                       "", R"(<float name="fov" value="40"/><string name="fovAxis" value="z"/>)"));
               }),
               Contains("fovAxis must be x, y, diagonal, smaller or larger"));
}

TEST_CASE("Mitsuba's colours: rgb as given, srgb and hex decoded, spectra integrated",
          "[mitsuba][import]") {
    const auto colorOf = [](const std::string &property, const std::string &emitter = "") {
        const std::string xml =
            importMitsuba(mitsubaScene(emitter.empty() ? "<bsdf type=\"diffuse\" id=\"b\">" +
                                                             property + "</bsdf>"
                                                       : emitter))
                .xml;
        return mitsubaColor(xml, emitter.empty() ? "albedo" : "radiance");
    };
    const Color3f rgb = colorOf(R"(<rgb name="reflectance" value="0.1 0.2 0.3"/>)");
    CHECK(rgb.r() == 0.1f);
    CHECK(rgb.b() == 0.3f);
    // sRGB: ((c + 0.055)/1.055)^2.4 above 0.04045, c/12.92 below.
    const Color3f srgb = colorOf(R"(<srgb name="reflectance" value="0.5, 0.02, 1"/>)");
    CHECK(srgb.r() == Approx(std::pow((0.5 + 0.055) / 1.055, 2.4)).epsilon(1e-6));
    CHECK(srgb.g() == Approx(0.02 / 12.92).epsilon(1e-6));
    CHECK(srgb.b() == Approx(1.0).epsilon(1e-6));
    const Color3f hex = colorOf(R"(<srgb name="reflectance" value="#ff8000"/>)");
    CHECK(hex.r() == Approx(1.0).epsilon(1e-6));
    CHECK(hex.g() == Approx(std::pow((128.0 / 255.0 + 0.055) / 1.055, 2.4)).epsilon(1e-6));
    CHECK(hex.b() == 0.0f);
    // A constant spectrum is that grey; a flat reflectance over the visible range is white.
    CHECK(colorOf(R"(<spectrum name="reflectance" value="0.25"/>)").g() == 0.25f);
    const Color3f flat = colorOf(R"(<spectrum name="reflectance" value="360:0.5, 830:0.5"/>)");
    CHECK(flat.r() == Approx(0.5).margin(2e-3));
    CHECK(flat.g() == Approx(0.5).margin(2e-3));
    CHECK(flat.b() == Approx(0.5).margin(2e-3));
    // A flat illuminant keeps its luminance: Y = 0.2126 R + 0.7152 G + 0.0722 B = 1.
    const Color3f light = colorOf("", R"(<shape type="sphere"><emitter type="area">
                <spectrum name="radiance" value="360:1, 830:1"/></emitter></shape>)");
    CHECK(0.2126f * light.r() + 0.7152f * light.g() + 0.0722f * light.b() ==
          Approx(1.0).margin(2e-3));
    CHECK(light.r() > light.b()); // illuminant E is redder than D65, sRGB's white
    // A blackbody is Planck's law per nanometre: hotter is bluer and brighter.
    const Color3f warm = colorOf("", R"(<shape type="sphere"><emitter type="area">
                <blackbody name="radiance" temperature="3000K"/></emitter></shape>)");
    const Color3f hot = colorOf("", R"(<shape type="sphere"><emitter type="area">
                <blackbody name="radiance" temperature="6500K"/></emitter></shape>)");
    CHECK(warm.r() / warm.b() > hot.r() / hot.b());
    CHECK(hot.g() > warm.g());
}

TEST_CASE("Mitsuba's depths count path vertices, ours bounces", "[mitsuba][import]") {
    const auto depthOf = [](int mitsubaDepth) {
        return int(mitsubaNumber(
            importMitsuba(mitsubaScene(fmt::format(
                              R"(<integrator type="path"><integer name="maxDepth" value="{}"/>
                                 </integrator>)",
                              mitsubaDepth)))
                .xml,
            "maxDepth"));
    };
    CHECK(depthOf(-1) == -1);
    CHECK(depthOf(1) == 0); // only the lights seen
    CHECK(depthOf(2) == 1); // direct illumination
    CHECK(depthOf(10) == 9);
    // Without an integrator, path tracing (Mitsuba's default), and 4 samples a pixel.
    const std::string xml = importMitsuba(mitsubaScene("")).xml;
    CHECK_THAT(xml, Contains("<integrator type=\"path_mis\""));
    CHECK(mitsubaNumber(xml, "sampleCount") == 4);
}

TEST_CASE("Mitsuba's integrators render bit for bit as ours they map onto",
          "[mitsuba][import][cli]") {
    // One small scene, written in both formats by hand; each case swaps the integrator.
    const char *mitsubaBody = R"(
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="{toWorld}"><lookat origin="0, 1, 4" target="0, 0.3, 0"/></transform>
        <sampler type="independent"><integer name="{sampleCount}" value="4"/></sampler>
        <film type="hdrfilm">
            <integer name="width" value="32"/><integer name="height" value="24"/>
            <rfilter type="box"/>
        </film>
    </sensor>
    <shape type="sphere">
        <point name="center" value="0, 0.5, 0"/><float name="radius" value="0.5"/>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.7, 0.4, 0.3"/></bsdf>
    </shape>
    <shape type="rectangle">
        <transform name="{toWorld}"><rotate x="1" angle="-90"/><scale value="3"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5, 0.5, 0.5"/></bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" value="1, 2.5, 1"/><float name="radius" value="0.3"/>
        <emitter type="area"><rgb name="radiance" value="20, 20, 20"/></emitter>
    </shape>)";
    const char *oursBody = R"(
    <sampler type="independent"><integer name="sampleCount" value="4"/></sampler>
    <camera type="perspective">
        <float name="fov" value="40"/>
        <integer name="width" value="32"/><integer name="height" value="24"/>
        <float name="nearClip" value="0.01"/>
        <transform name="toWorld"><lookat origin="0, 1, 4" target="0, 0.3, 0" up="0, 1, 0"/></transform>
        <rfilter type="box"/>
    </camera>
    <mesh type="sphere"><string name="convention" value="mitsuba"/>
        <point name="center" value="0, 0.5, 0"/><float name="radius" value="0.5"/>
        <bsdf type="diffuse"><color name="albedo" value="0.7, 0.4, 0.3"/></bsdf>
    </mesh>
    <mesh type="rectangle">
        <transform name="toWorld"><rotate axis="1, 0, 0" angle="-90"/><scale value="3"/></transform>
        <bsdf type="diffuse"><color name="albedo" value="0.5, 0.5, 0.5"/></bsdf>
    </mesh>
    <mesh type="sphere"><string name="convention" value="mitsuba"/>
        <point name="center" value="1, 2.5, 1"/><float name="radius" value="0.3"/>
        <emitter type="area"><color name="radiance" value="20, 20, 20"/></emitter>
    </mesh>)";
    struct Case {
        std::string version, mitsuba, ours;
    };
    // Depths: Mitsuba counts path vertices (maxDepth 5: four bounces), we count bounces.
    const std::vector<Case> cases = {
        {"0.6.0", R"(<integrator type="direct"/>)", R"(<integrator type="direct_mis"/>)"},
        {"0.6.0", R"(<integrator type="bdpt"><integer name="maxDepth" value="5"/></integrator>)",
         R"(<integrator type="bdpt"><integer name="maxDepth" value="4"/></integrator>)"},
        {"3.0.0",
         R"(<integrator type="ptracer"><integer name="max_depth" value="4"/></integrator>)",
         R"(<integrator type="lighttracer"><integer name="maxDepth" value="3"/></integrator>)"},
        {"3.0.0", R"(<integrator type="volpath_simple"><integer name="max_depth" value="6"/>
                     <integer name="rr_depth" value="3"/></integrator>)",
         R"(<integrator type="volpath"><integer name="maxDepth" value="5"/>
                     <integer name="rrDepth" value="2"/></integrator>)"},
        {"0.6.0", R"(<integrator type="ao"><integer name="shadingSamples" value="2"/>
                     <float name="rayLength" value="1.5"/></integrator>)",
         R"(<integrator type="ao"><integer name="sampleCount" value="2"/>
                     <float name="length" value="1.5"/></integrator>)"},
        {"0.6.0", R"(<integrator type="photonmapper"><integer name="globalPhotons" value="20000"/>
                     <float name="globalLookupRadius" value="0.1"/></integrator>)",
         R"(<integrator type="photonmapper"><integer name="photonCount" value="20000"/>
                     <float name="photonRadius" value="0.1"/></integrator>)"},
        {"0.6.0", R"(<integrator type="sppm"><integer name="photonCount" value="20000"/>
                     <float name="initialRadius" value="0.1"/>
                     <float name="alpha" value="0.6"/></integrator>)",
         R"(<integrator type="progressivephotonmapper"><integer name="photonCount" value="20000"/>
                     <float name="photonRadius" value="0.1"/>
                     <float name="alpha" value="0.6"/></integrator>)"},
        {"3.0.0", R"(<integrator type="aov"><string name="aovs" value="dd.y:depth,nn:sh_normal"/>
                     <integrator type="path"/></integrator>)",
         R"(<integrator type="path_mis"><string name="aovs" value="depth,normal"/></integrator>)"}};
    const TempDir dir;
    int index = 0;
    for (const Case &c : cases) {
        CAPTURE(c.mitsuba);
        const bool snake = c.version[0] == '3';
        const std::string body =
            fmt::format(mitsubaBody, fmt::arg("toWorld", snake ? "to_world" : "toWorld"),
                        fmt::arg("sampleCount", snake ? "sample_count" : "sampleCount"));
        const std::string mitsubaFile = fmt::format("mitsuba{}.xml", index);
        const std::string oursFile = fmt::format("ours{}.xml", index);
        ++index;
        dir.write(mitsubaFile,
                  fmt::format("<scene version=\"{}\">{}{}</scene>", c.version, c.mitsuba, body));
        dir.write(oursFile, "<scene>" + c.ours + oursBody + "</scene>");
        std::vector<Bitmap> images;
        for (const std::string &file : {mitsubaFile, oursFile}) {
            const ProcessResult result = runNori({(dir.path() / file).string(), "--no-progress"});
            INFO(file << ": " << result.output);
            REQUIRE(result.exitCode == 0);
            CHECK_THAT(result.output, !Contains("Warning"));
            images.push_back(
                readImageFile((dir.path() / fs::path(file).stem()).string() + ".exr").pixels);
        }
        CHECK(identicalImages(images[0], images[1]));
    }
}

TEST_CASE("Mitsuba's variables, includes and references", "[mitsuba][import]") {
    const TempDir dir;
    dir.write("part.xml", R"(<scene version="0.6.0">
        <bsdf type="diffuse" id="grey"><rgb name="reflectance" value="$albedo"/></bsdf>
    </scene>)");
    const std::string main =
        dir.write("main.xml", mitsubaScene(R"(<default name="albedo" value="0.3"/>
            <include filename="part.xml"/>
            <shape type="sphere"><ref id="grey"/></shape>)"));
    mitsuba::ConvertOptions options;
    const std::string withDefault = mitsuba::convertFile(main, options).xml;
    CHECK(mitsubaColor(withDefault, "albedo").g() == 0.3f);
    CHECK_THAT(withDefault, Contains("<ref id=\"grey\""));
    options.defines["albedo"] = "0.7";
    CHECK(mitsubaColor(mitsuba::convertFile(main, options).xml, "albedo").g() == 0.7f);
    // An undefined variable, a missing include and a reference to nothing are located.
    CHECK_THAT(errorOf([] {
                   importMitsuba(mitsubaScene(
                       R"(<bsdf type="diffuse"><float name="alpha" value="$missing"/></bsdf>)"));
               }),
               Contains("test.xml:") && Contains("$missing is not defined"));
    CHECK_THAT(errorOf([] {
                   importMitsuba(
                       mitsubaScene(R"(<shape type="sphere"><ref id="nothing"/></shape>)"));
               }),
               Contains("test.xml:") && Contains("no object has that id"));
}

TEST_CASE("Mitsuba files with mistakes are located errors with suggestions", "[mitsuba][import]") {
    CHECK_THAT(errorOf([] { importMitsuba(mitsubaScene(R"(<bsdf type="roughplastc"/>)")); }),
               Contains("test.xml:8:5") && Contains("unknown bsdf 'roughplastc'") &&
                   Contains("roughplastic"));
    CHECK_THAT(errorOf([] {
                   importMitsuba(mitsubaScene(
                       R"(<bsdf type="plastic"><float name="intIRO" value="1.5"/></bsdf>)"));
               }),
               Contains("test.xml:8:26") && Contains("bsdf 'plastic' has no parameter 'intIRO'") &&
                   Contains("intIOR"));
    CHECK_THAT(errorOf([] { importMitsuba("<scene version=\"0.6.0\"><shape type=\"sphere\">"); }),
               Contains("test.xml:1:") && Contains("malformed XML"));
    CHECK_THAT(errorOf([] {
                   importMitsuba(
                       "<scene version=\"0.6.0\"><sensor type=\"orthographic\"/></scene>");
               }),
               Contains("the 'orthographic' sensor is not supported"));
    // A known plugin we do not have: a warning naming its stand-in.
    const mitsuba::Conversion hair =
        importMitsuba(mitsubaScene(R"(<bsdf type="phong"><float name="exponent" value="98"/>
                                      </bsdf><shape type="hair"/>)"));
    REQUIRE(hair.warnings.size() == 2);
    CHECK_THAT(hair.warnings[0], Contains("phong is approximated by roughplastic"));
    CHECK_THAT(hair.warnings[1], Contains("'hair' shape is not supported: left out"));
}

TEST_CASE("A mirrored Mitsuba rectangle faces its transformed normal", "[mitsuba][import]") {
    // Mitsuba's rectangle faces (0, 0, 1) transformed as a normal; ours faces its winding,
    // which a mirror turns over: the importer turns it back (staircase2's door light).
    const auto flipped = [](const std::string &scale) {
        return importMitsuba(mitsubaScene(fmt::format(
                                 R"(<shape type="rectangle"><transform name="toWorld">
                                    <scale {}/></transform></shape>)",
                                 scale)))
                   .xml.find("flipNormals") != std::string::npos;
    };
    CHECK_FALSE(flipped(R"(value="2")"));
    CHECK(flipped(R"(x="-1")"));
    CHECK_FALSE(flipped(R"(x="-1" y="-1")"));
}

TEST_CASE("Mitsuba 3's names are Mitsuba 0.6's in snake_case", "[mitsuba][import]") {
    const std::string xml = importMitsuba(mitsubaScene(R"(<bsdf type="roughdielectric">
                <float name="int_ior" value="1.33"/><float name="alpha_u" value="0.1"/>
                <float name="alpha_v" value="0.3"/></bsdf>)",
                                                       R"(<float name="fov" value="40"/>
                <string name="fov_axis" value="x"/>)",
                                                       "3.0.0"))
                                .xml;
    CHECK(mitsubaNumber(xml, "intIOR") == Approx(1.33));
    CHECK(mitsubaNumber(xml, "alphaU") == Approx(0.1));
    CHECK(mitsubaNumber(xml, "alphaV") == Approx(0.3));
    // In a 0.6 file the other spelling is read with a warning, as Mitsuba warns of it.
    const mitsuba::Conversion mixed = importMitsuba(
        mitsubaScene(R"(<bsdf type="dielectric"><float name="int_ior" value="1.33"/></bsdf>)"));
    CHECK(mitsubaNumber(mixed.xml, "intIOR") == Approx(1.33));
    REQUIRE(mixed.warnings.size() == 1);
    CHECK_THAT(mixed.warnings[0], Contains("'int_ior' is the spelling of another Mitsuba version"));
    // A name of neither dialect is an error.
    CHECK_THAT(errorOf([] {
                   importMitsuba(mitsubaScene(
                       R"(<bsdf type="dielectric"><float name="int_iro" value="1.33"/></bsdf>)"));
               }),
               Contains("no parameter 'int_iro'") && Contains("intIOR"));
}

TEST_CASE("Mitsuba plugins we do not have: one warning each, naming the stand-in",
          "[mitsuba][import]") {
    // phong and ward: our rough plastic, Beckmann α = √(2/(n + 2)) and √(αu·αv).
    const mitsuba::Conversion phong = importMitsuba(mitsubaScene(R"(<shape type="sphere">
        <bsdf type="phong"><float name="exponent" value="48"/>
            <rgb name="diffuseReflectance" value="0.3, 0.2, 0.1"/></bsdf></shape>)"));
    REQUIRE(phong.warnings.size() == 1);
    CHECK_THAT(phong.warnings[0], Contains("phong is approximated by roughplastic"));
    CHECK_THAT(phong.xml, Contains("<bsdf type=\"roughplastic\""));
    CHECK(mitsubaNumber(phong.xml, "alpha") == Approx(std::sqrt(2.0 / 50.0)));
    CHECK(mitsubaColor(phong.xml, "diffuseReflectance").r() == Approx(0.3f));
    const mitsuba::Conversion ward = importMitsuba(mitsubaScene(R"(<shape type="sphere">
        <bsdf type="ward"><float name="alphaU" value="0.1"/><float name="alphaV" value="0.4"/>
        </bsdf></shape>)"));
    REQUIRE(ward.warnings.size() == 1);
    CHECK_THAT(ward.warnings[0], Contains("ward is approximated by roughplastic"));
    CHECK(mitsubaNumber(ward.xml, "alpha") == Approx(0.2));
    // The sun and sky: a distant disk of the sun's angular size toward sunDirection and a
    // constant sky, in one warning.
    const mitsuba::Conversion sunsky = importMitsuba(mitsubaScene(R"(<emitter type="sunsky">
        <vector name="sunDirection" value="0, 1, 1"/></emitter>)"));
    REQUIRE(sunsky.warnings.size() == 1);
    CHECK_THAT(sunsky.warnings[0],
               Contains("a distant disk of the sun's size") && Contains("a constant sky"));
    CHECK_THAT(sunsky.xml,
               Contains("<emitter type=\"distantdisk\"") && Contains("<emitter type=\"constant\""));
    const mitsuba::Conversion sky = importMitsuba(mitsubaScene(R"(<emitter type="sky"/>)"));
    REQUIRE(sky.warnings.size() == 1);
    CHECK_THAT(sky.xml, !Contains("distantdisk") && Contains("<emitter type=\"constant\""));
    CHECK_THAT(sky.warnings[0], !Contains("overhead"));
    const mitsuba::Conversion sun = importMitsuba(mitsubaScene(R"(<emitter type="sun"/>)"));
    REQUIRE(sun.warnings.size() == 1);
    CHECK_THAT(sun.warnings[0], Contains("the sun is overhead"));
    CHECK_THAT(sun.xml, Contains("distantdisk") && !Contains("<emitter type=\"constant\""));
    // Without a coat: the nested BSDF alone.
    const mitsuba::Conversion coating = importMitsuba(mitsubaScene(R"(<shape type="sphere">
        <bsdf type="coating"><bsdf type="diffuse"/></bsdf></shape>)"));
    REQUIRE(coating.warnings.size() == 1);
    CHECK_THAT(coating.warnings[0], Contains("without the coat"));
    CHECK_THAT(coating.xml, Contains("<bsdf type=\"diffuse\""));
}

TEST_CASE("Mitsuba's crop window, clip planes and material 'none' carry over",
          "[mitsuba][import]") {
    const std::string xml = importMitsuba(R"(<scene version="0.6.0">
        <sensor type="perspective">
            <float name="fov" value="40"/>
            <float name="nearClip" value="0.5"/><float name="farClip" value="80"/>
            <film type="hdrfilm">
                <integer name="width" value="200"/><integer name="height" value="100"/>
                <integer name="cropOffsetX" value="20"/><integer name="cropOffsetY" value="10"/>
                <integer name="cropWidth" value="50"/><integer name="cropHeight" value="40"/>
            </film>
        </sensor>
        <shape type="sphere">
            <bsdf type="conductor"><string name="material" value="none"/></bsdf>
        </shape>
    </scene>)")
                                .xml;
    CHECK(mitsubaNumber(xml, "nearClip") == 0.5);
    CHECK(mitsubaNumber(xml, "farClip") == 80);
    CHECK(mitsubaNumber(xml, "cropOffsetX") == 20);
    CHECK(mitsubaNumber(xml, "cropOffsetY") == 10);
    CHECK(mitsubaNumber(xml, "cropWidth") == 50);
    CHECK(mitsubaNumber(xml, "cropHeight") == 40);
    // material "none" (η = 0, k = 1: a perfect mirror) is one of our conductor's names.
    CHECK_THAT(xml, Contains("<bsdf type=\"conductor\"") &&
                        Contains("name=\"material\" value=\"none\""));
}
