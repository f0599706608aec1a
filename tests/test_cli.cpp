// The `nori` program as a user runs it: output files, options, errors and Ctrl-C.
#include <nori/bitmap.h>
#include <nori/filesystem.h>
#include <nori/statistics.h>

#include "testutil.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>

using namespace nori;
using Catch::Contains;
using nori::testing::ProcessResult;
using nori::testing::runCommand;
using nori::testing::runNori;
using nori::testing::TempDir;

namespace {

/// A small AO scene; $spp and $size can be set with -D.
const char *kScene = R"(<?xml version="1.0"?>
<scene>
    <default name="spp" value="2"/>
    <default name="size" value="48"/>
    <integrator type="ao"/>
    <sampler type="independent"><integer name="sampleCount" value="$spp"/></sampler>
    <camera type="perspective">
        <integer name="width" value="$size"/><integer name="height" value="$size"/>
        <transform name="toWorld"><lookat origin="0,1,5" target="0,0.5,0"/></transform>
    </camera>
    <mesh type="sphere"><point name="center" value="0,1,0"/></mesh>
    <mesh type="obj"><string name="filename" value="meshes/floor.obj"/></mesh>
</scene>
)";

const char *kFloor = "v -5 0 -5\nv -5 0 5\nv 5 0 5\nv 5 0 -5\nf 1 2 3 4\n";

} // namespace

TEST_CASE("nori renders a scene to EXR and PNG next to it", "[cli]") {
    TempDir dir;
    dir.write("meshes/floor.obj", kFloor);
    const std::string scene = dir.write("scene.xml", kScene);
    auto result = runNori({scene});
    INFO(result.output);
    REQUIRE(result.exitCode == 0);
    CHECK_THAT(result.output, Contains("Rendering: 100%") && Contains("Done in") &&
                                  Contains("Loaded " + scene + " in "));
    // Statistics as Nori and pbrt print them: the scene first, rays at the end.
    CHECK_THAT(result.output, Contains("Scene: 2 shapes (2 triangles), 0 emitters; BVH of 3 "
                                       "primitives built in") &&
                                  Contains(" M rays traced, ") && Contains(" M rays/s)"));
    Bitmap image = Bitmap::load((dir.path() / "scene.exr").string());
    CHECK(image.width() == 48);
    CHECK(std::filesystem::exists(dir.path() / "scene.png"));

    SECTION("-o names the output; -D overrides a <default>") {
        const std::string out = (dir.path() / "renders" / "out.exr").string();
        std::filesystem::create_directories(dir.path() / "renders");
        auto custom = runNori({"-D", "size=24", "-Dspp=1", "-o", out, "--no-progress", scene});
        INFO(custom.output);
        REQUIRE(custom.exitCode == 0);
        CHECK(Bitmap::load(out).width() == 24);
        CHECK(std::filesystem::exists(dir.path() / "renders" / "out.png"));
        CHECK_THAT(custom.output, !Contains("Rendering:"));
        CHECK_THAT(custom.output, !Contains("Warning: -D"));
    }

    SECTION("--seed gives a render its own noise; a seed given twice, the same image") {
        const auto render = [&](const std::string &seed, const std::string &name) {
            const std::string out = (dir.path() / name).string();
            auto run = runNori({"--seed", seed, "-o", out, "--no-progress", scene});
            INFO(run.output);
            REQUIRE(run.exitCode == 0);
            return Bitmap::load(out + ".exr");
        };
        const Bitmap first = render("7", "seed7"), again = render("7", "seed7-again");
        const Bitmap other = render("8", "seed8");
        CHECK(nori::testing::identicalImages(first, again));
        CHECK(!nori::testing::identicalImages(first, other));
        CHECK(!nori::testing::identicalImages(first, image)); // the scene's own seed, 0
    }

    SECTION("a -D that the scene never uses is a warning naming it") {
        auto unused = runNori({"-D", "sppp=8", "--no-progress", scene});
        INFO(unused.output);
        REQUIRE(unused.exitCode == 0);
        CHECK_THAT(unused.output, Contains("Warning: -D sppp=8 is not used") &&
                                      Contains("scene.xml has no $sppp"));
    }
}

TEST_CASE("nori reports a misspelled property with file:line and did-you-mean", "[cli]") {
    TempDir dir;
    const std::string scene = dir.write("typo.xml", R"(<scene>
    <integrator type="ao">
        <float name="lenght" value="2"/>
    </integrator>
    <camera type="perspective"/>
</scene>)");
    auto result = runNori({scene});
    CHECK(result.exitCode == 1);
    CHECK_THAT(result.output, Contains("typo.xml:3:10") && Contains("'lenght'") &&
                                  Contains("integrator 'ao'") &&
                                  Contains("did you mean 'length'?"));
}

TEST_CASE("nori reports bad input files and options without crashing", "[cli]") {
    TempDir dir;
    const std::string brokenObj = dir.write("broken.obj", "v 0 0 0\nv 1 0 0\nf 1 2 7\n");
    const std::string scene = dir.write("scene.xml", R"(<scene>
    <integrator type="normals"/><camera type="perspective"/>
    <mesh type="obj"><string name="filename" value="broken.obj"/></mesh>
</scene>)");
    auto objResult = runNori({scene});
    CHECK(objResult.exitCode == 1);
    CHECK_THAT(objResult.output, Contains("scene.xml:3:6") && Contains("broken.obj:3:") &&
                                     Contains("vertex index 7 is out of range"));

    auto missing = runNori({(dir.path() / "nothing.xml").string()});
    CHECK(missing.exitCode == 1);
    CHECK_THAT(missing.output, Contains("cannot open XML scene file") && Contains("nothing.xml"));

    auto badOption = runNori({"--sppp", "4", scene});
    CHECK(badOption.exitCode == 1);
    CHECK_THAT(badOption.output, Contains("unknown option '--sppp'"));

    auto badValue = runNori({"--spp", "0", scene});
    CHECK(badValue.exitCode == 1);
    CHECK_THAT(badValue.output, Contains("--spp must be a positive integer"));

    auto badPort = runNori({"--preview", "70000", scene});
    CHECK(badPort.exitCode == 1);
    CHECK_THAT(badPort.output, Contains("--preview PORT must lie in [1, 65535], got 70000"));
    auto previewOfPluginTest = runNori({"--preview", "--test-plugin", "diffuse"});
    CHECK(previewOfPluginTest.exitCode == 1);
    CHECK_THAT(previewOfPluginTest.output, Contains("--preview shows a render or a test file"));
    auto previewOfMerge = runNori({"merge", "a.exr", "-o", "b", "--preview-wait"});
    CHECK(previewOfMerge.exitCode == 1);
    CHECK_THAT(previewOfMerge.output, Contains("merge: --preview-wait applies to rendering"));
}

TEST_CASE("nori --list-plugins prints every plugin by kind", "[cli]") {
    auto result = runNori({"--list-plugins"});
    CHECK(result.exitCode == 0);
    // Kinds in order, each followed by its plugins, sorted, each with its summary.
    CHECK_THAT(result.output, Contains("integrator:\n  ao ") && Contains("\n  av ") &&
                                  Contains("rfilter:\n  box ") &&
                                  Contains("emitter:\n  area             a diffuse area light") &&
                                  Contains("\n  point            an isotropic point light."));
}

TEST_CASE("Ctrl-C writes the finished passes: a whole frame with the full render's mean", "[cli]") {
    TempDir dir;
    dir.write("meshes/floor.obj", kFloor);
    const std::string scene = dir.write("slow.xml", kScene);
    // Passes of 1, 1, 2, 4, ..., 64 spp: the 10% progress line (100 of 1000 spp) comes
    // during the eighth pass (64 to 128 spp); interrupted there, nori keeps 64 spp.
    auto result = runNori({"-D", "size=128", "--spp", "1000", scene}, " 10% (");
    INFO(result.output);
    CHECK(result.exitCode == 130);
    CHECK_THAT(result.output, Contains("Interrupted: wrote the") && Contains(" of 1000 spp"));
    CHECK_FALSE(std::filesystem::exists(dir.path() / "slow.exr"));
    REQUIRE(std::filesystem::exists(dir.path() / "slow_partial.png"));
    const Bitmap partial = Bitmap::load((dir.path() / "slow_partial.exr").string());

    // The reference: the whole render at 256 spp.
    auto full = runNori({"-D", "size=128", "--spp", "256", "--no-progress", "-o",
                         (dir.path() / "full").string(), scene});
    REQUIRE(full.exitCode == 0);
    const Bitmap reference = Bitmap::load((dir.path() / "full.exr").string());

    // A whole frame: no black pixel (AO is positive wherever a ray hits the scene, and
    // the floor fills the lower half), and per-pixel differences of mean zero (t-test;
    // both images estimate the same expectation, whatever their sample counts).
    auto differenceTest = [&](float scale) {
        RunningMoments differences;
        for (int y = 0; y < partial.height(); ++y)
            for (int x = 0; x < partial.width(); ++x)
                differences.add(scale * partial(y, x).r() - reference(y, x).r());
        return studentTTest(differences.mean, differences.variance(), differences.count, 0.0, 0.01);
    };
    int black = 0;
    for (int y = partial.height() / 2; y < partial.height(); ++y)
        for (int x = 0; x < partial.width(); ++x)
            black += partial(y, x).maxCoeff() == 0.0f ? 1 : 0;
    CHECK(black == 0);
    const StudentTResult same = differenceTest(1.0f);
    INFO("t = " << same.t);
    CHECK(same.passed);
    // Negative control: normalised 1% wrong (as by one sample too many), it is rejected.
    CHECK_FALSE(differenceTest(1.01f).passed);
}

TEST_CASE("Ctrl-C is honoured within a pixel, even at 10^9 samples per pixel", "[cli]") {
    // A pass of 64 spp at 10^9 spp would take long; cancellation is checked every sample.
    // Interrupt as soon as rendering starts: nori must stop at once.
    TempDir dir;
    dir.write("meshes/floor.obj", kFloor);
    const std::string scene = dir.write("slow.xml", kScene);
    auto result = runNori({"-D", "size=32", "--spp", "1000000000", scene}, "spp,");
    INFO(result.output);
    CHECK(result.exitCode == 130);
    // The first passes (1, 1, 2 spp) may finish before the signal lands: either way
    // nori stops within the pass under way, far from 10^9 spp.
    CHECK_THAT(result.output, Contains("Interrupted"));
}

TEST_CASE("The exposure option brightens the PNG by 2^E and leaves the EXR alone, and --version",
          "[cli]") {
    TempDir dir;
    dir.write("meshes/floor.obj", kFloor);
    const std::string scene = dir.write("scene.xml", kScene);
    auto plain = runNori({"--no-progress", "-o", (dir.path() / "plain").string(), scene});
    auto bright = runNori(
        {"--no-progress", "--exposure", "1", "-o", (dir.path() / "bright").string(), scene});
    REQUIRE(plain.exitCode == 0);
    REQUIRE(bright.exitCode == 0);
    const Bitmap exr0 = Bitmap::load((dir.path() / "plain.exr").string());
    const Bitmap exr1 = Bitmap::load((dir.path() / "bright.exr").string());
    const Bitmap png0 = Bitmap::load((dir.path() / "plain.png").string());
    const Bitmap png1 = Bitmap::load((dir.path() / "bright.png").string());
    int compared = 0;
    for (int y = 0; y < exr0.height(); ++y)
        for (int x = 0; x < exr0.width(); ++x) {
            REQUIRE((exr0(y, x) == exr1(y, x)).all());
            // Unclipped pixels: twice as bright in linear terms, up to 8-bit rounding.
            const float v0 = png0(y, x).g(), v1 = png1(y, x).g();
            if (v0 > 0.05f && v1 < 0.95f) {
                CHECK(v1 == Approx(2.0f * v0).epsilon(0.05));
                ++compared;
            }
        }
    CHECK(compared > 100);

    auto version = runNori({"--version"});
    CHECK(version.exitCode == 0);
    // The version, then the build: its type, instruction set, compiler, precompiled
    // headers and sanitizers (issue: a user's report says how nori was built).
    CHECK_THAT(version.output,
               Catch::Matches("nori [0-9]+\\.[0-9]+\\.[0-9]+\nbuild type [A-Za-z]+, "
                              "(AVX-512|AVX2|AVX|SSE4\\.2|SSE2) \\((-march=native|portable "
                              "x86-64)\\), (GCC|clang) [0-9.]+, precompiled headers (on|off), "
                              "sanitizers (off|ASan\\+UBSan|TSan)\n"));
    auto badExposure = runNori({"--exposure", "nan", scene});
    CHECK(badExposure.exitCode == 1);
}

TEST_CASE("A write that fails keeps the previous image and says why", "[cli][output]") {
    TempDir dir;
    dir.write("meshes/floor.obj", kFloor);
    const std::string scene = dir.write("scene.xml", kScene);
    const std::string stem = (dir.path() / "out" / "image").string();
    std::filesystem::create_directories(dir.path() / "out");
    REQUIRE(runNori({"--no-progress", "-o", stem, scene}).exitCode == 0);
    const std::string exr = readBinaryFile(stem + ".exr", "EXR"),
                      png = readBinaryFile(stem + ".png", "PNG");
    const auto leftovers = [&] {
        std::vector<std::string> names;
        for (const auto &entry : std::filesystem::directory_iterator(dir.path() / "out"))
            names.push_back(entry.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    };
    // A file size limit below the new EXR's size (the EXR of 192² pixels is larger than
    // 20 kB): the write fails, the previous files stay, no temporary file is left.
    const ProcessResult limited =
        runCommand("/usr/bin/prlimit", {"--fsize=20000", NORI_EXECUTABLE, "--no-progress",
                                        "-Dsize=192", "-o", stem, scene});
    INFO(limited.output);
    CHECK(limited.exitCode == 1);
    CHECK_THAT(limited.output,
               Contains("cannot write EXR image '" + stem + ".exr': File too large"));
    CHECK(readBinaryFile(stem + ".exr", "EXR") == exr);
    CHECK(readBinaryFile(stem + ".png", "PNG") == png);
    CHECK(leftovers() == std::vector<std::string>{"image.exr", "image.png"});
    // nori-imgtool's writes go the same way.
    const ProcessResult converted =
        runCommand("/usr/bin/prlimit",
                   {"--fsize=100", IMGTOOL_EXECUTABLE, "convert", stem + ".exr", stem + ".png"});
    INFO(converted.output);
    CHECK(converted.exitCode != 0);
    CHECK_THAT(converted.output,
               Contains("cannot write PNG image '" + stem + ".png': File too large"));
    CHECK(readBinaryFile(stem + ".png", "PNG") == png);
    CHECK(leftovers() == std::vector<std::string>{"image.exr", "image.png"});
    // An output folder that is a file: the reason is named.
    dir.write("not-a-folder", "text");
    const ProcessResult misplaced =
        runNori({"--no-progress", "-o", (dir.path() / "not-a-folder" / "image").string(), scene});
    CHECK(misplaced.exitCode == 1);
    CHECK_THAT(misplaced.output, Contains("not-a-folder/image.exr': Not a directory"));
}

TEST_CASE("The plugin listing and --help say what is tested and what the scene is",
          "[cli][plugins]") {
    const ProcessResult list = runNori({"--list-plugins"});
    REQUIRE(list.exitCode == 0);
    // The first entry a student sees is our own scene: built in, not "undocumented".
    const std::string sceneLine = list.output.substr(0, list.output.find("\n\n"));
    CHECK_THAT(sceneLine,
               Contains("the root element of every scene file") && !Contains("undocumented"));
    CHECK_THAT(runNori({"--list-plugins", "scene"}).output,
               Contains("the root element of every scene file"));
    // --help names what --test-plugin covers, integrators included.
    // (The help wraps its lines: compared with runs of spaces and line breaks as one space.)
    std::string help;
    for (char c : runNori({"--help"}).output)
        if (!std::isspace(static_cast<unsigned char>(c)) || (!help.empty() && help.back() != ' '))
            help += std::isspace(static_cast<unsigned char>(c)) ? ' ' : c;
    CHECK_THAT(help, Contains("an integrator against the built-in of its quantity"));
    CHECK_THAT(help, !Contains("test sampling plugins (BSDFs, phase functions, emitters)"));
}
