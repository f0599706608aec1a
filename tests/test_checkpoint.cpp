// Checkpoints (RenderOptions::checkpoint, app/checkpoint.h): a render resumed from any of
// its checkpoints writes the uninterrupted render's image bit for bit, for every kind of
// state a render keeps (the film's sums, splats, adaptive sampling's statistics, the
// progressive photon mapper's radii, a part's slice); `nori` killed at random moments
// resumes to the same EXR; checkpoints of anything else are refused, saying what differs.
#include "app/checkpoint.h"
#include "app/renderpart.h"
#include <nori/filesystem.h>
#include <nori/imagefile.h>
#include <nori/pcg32.h>
#include <nori/render.h>

#include "testutil.h"

#include <catch2/catch.hpp>

#include <chrono>
#include <csignal>
#include <filesystem>

using namespace nori;
using namespace nori::testing;
namespace fs = std::filesystem;

namespace {

/// A small lit box: a glossy sphere and a diffuse floor under a spherical light, with
/// `integrator`, `sampler` and `extra` (a medium) in it.
std::string checkpointScene(const std::string &integrator, const std::string &sampler,
                            const std::string &extra = "") {
    return fmt::format(R"(<scene>
        {}
        {}
        <camera type="perspective">
            <float name="fov" value="45"/>
            <integer name="width" value="24"/> <integer name="height" value="16"/>
            <transform name="toWorld"><lookat origin="0, 1, 4" target="0, 0.4, 0" up="0, 1, 0"/></transform>
        </camera>
        <mesh type="sphere"><point name="center" value="0, 0.5, 0"/><float name="radius" value="0.5"/>
            <bsdf type="roughconductor"><float name="alpha" value="0.2"/></bsdf></mesh>
        <mesh type="rectangle">
            <transform name="toWorld"><rotate axis="1, 0, 0" angle="-90"/><scale value="3"/></transform>
            <bsdf type="diffuse"><color name="albedo" value="0.6, 0.5, 0.4"/></bsdf></mesh>
        <mesh type="sphere"><point name="center" value="1, 2.5, 1"/><float name="radius" value="0.3"/>
            <emitter type="area"><color name="radiance" value="20"/></emitter></mesh>
        {}
    </scene>)",
                       integrator, sampler, extra);
}

/// Every channel of two images equal bit for bit.
bool identicalLayers(const LayeredImage &a, const LayeredImage &b) {
    if (a.size() != b.size() || a.channels().size() != b.channels().size())
        return false;
    for (const auto &[name, values] : a.channels()) {
        const auto other = b.channels().find(name);
        if (other == b.channels().end() || !(other->second == values).all())
            return false;
    }
    return true;
}

/// A render of the scene, or of its part `part`, optionally resumed from `state`, handing
/// every checkpoint (one after every pass) to `states`.
RenderResult renderWithCheckpoints(const std::string &xml, std::vector<std::string> *states,
                                   const std::string *state = nullptr,
                                   const PartSpec *part = nullptr) {
    auto scene = loadScene(xml);
    RenderOptions options = quietOptions(2);
    options.aovs = {AOV::Albedo, AOV::Variance, AOV::SampleCount};
    options.resumeState = state;
    if (states) {
        options.checkpointSeconds = 0.0;
        options.checkpoint = [states](const std::string &bytes) { states->push_back(bytes); };
    }
    return part ? renderPart(*scene, options, *part, "0123456789abcdef", "test")
                : renderScene(*scene, options);
}

} // namespace

TEST_CASE("A render resumed from any of its checkpoints is the uninterrupted render, bit for "
          "bit",
          "[render][checkpoint]") {
    const char *independent16 =
        R"(<sampler type="independent"><integer name="sampleCount" value="16"/></sampler>)";
    const PartSpec part{2, 3};
    struct Case {
        std::string name, xml;
        const PartSpec *part = nullptr;
    };
    const std::vector<Case> cases = {
        {"path_mis", checkpointScene(R"(<integrator type="path_mis"/>)", independent16)},
        {"volpath through fog", checkpointScene(R"(<integrator type="volpath"/>)", independent16,
                                                R"(<medium type="homogeneous" id="fog">
                                <color name="sigmaS" value="0.3"/><color name="sigmaA" value="0.05"/>
                            </medium>
                            <mesh type="sphere"><float name="radius" value="10"/>
                                <ref name="interior" id="fog"/><bsdf type="null"/></mesh>)")},
        {"bdpt (splats)", checkpointScene(R"(<integrator type="bdpt"/>)", independent16)},
        {"progressive photon mapper",
         checkpointScene(R"(<integrator type="progressivephotonmapper">
                                <integer name="photonCount" value="3000"/></integrator>)",
                         R"(<sampler type="independent"><integer name="sampleCount" value="5"/>
                            </sampler>)")},
        {"adaptive sampling",
         checkpointScene(R"(<integrator type="path_mis"/>)",
                         R"(<sampler type="independent"><integer name="sampleCount" value="64"/>
                                <float name="maxTolerance" value="0.2"/>
                                <integer name="minSamples" value="4"/></sampler>)")},
        {"part 2 of 3", checkpointScene(R"(<integrator type="path_mis"/>)", independent16), &part},
    };
    for (const Case &c : cases) {
        INFO(c.name);
        std::vector<std::string> states;
        const RenderResult uninterrupted = renderWithCheckpoints(c.xml, &states, nullptr, c.part);
        REQUIRE(uninterrupted.complete);
        REQUIRE(states.size() + 1 >= 3); // a checkpoint after every pass but the last
        // Writing checkpoints changes nothing.
        CHECK(identicalLayers(uninterrupted.layers,
                              renderWithCheckpoints(c.xml, nullptr, nullptr, c.part).layers));
        for (size_t k = 0; k < states.size(); ++k) {
            INFO("resumed from checkpoint " << k + 1 << " of " << states.size());
            std::vector<std::string> later;
            const RenderResult resumed = renderWithCheckpoints(c.xml, &later, &states[k], c.part);
            CHECK(resumed.resumedSamplesPerPixel > 0);
            CHECK(resumed.complete);
            CHECK(resumed.passes == uninterrupted.passes);
            CHECK(resumed.samplesTaken == uninterrupted.samplesTaken);
            CHECK(identicalLayers(uninterrupted.layers, resumed.layers));
            // The resumed render's own checkpoints are those of the uninterrupted one.
            REQUIRE(later.size() == states.size() - k - 1);
        }
    }
}

TEST_CASE("A resumed render's time budget counts the time its earlier runs spent",
          "[render][checkpoint]") {
    const std::string xml = checkpointScene(
        R"(<integrator type="path_mis"/>)",
        R"(<sampler type="independent"><integer name="sampleCount" value="64"/></sampler>)");
    std::vector<std::string> states;
    renderWithCheckpoints(xml, &states);
    REQUIRE(states.size() >= 2);
    const std::string &state = states[1]; // after 2 spp
    auto scene = loadScene(xml);
    RenderOptions options = quietOptions(2);
    options.aovs = {AOV::Albedo, AOV::Variance, AOV::SampleCount}; // as the checkpoint's
    options.resumeState = &state;
    // A budget the first run already spent: no pass more.
    options.timeBudget = 1e-9;
    const RenderResult spent = renderScene(*scene, options);
    CHECK(spent.samplesPerPixel == 2);
    CHECK_FALSE(spent.complete);
    CHECK(spent.seconds > 0.0);
    // Control: an ample budget finishes the render.
    auto again = loadScene(xml);
    options.timeBudget = 1000.0;
    const RenderResult finished = renderScene(*again, options);
    CHECK(finished.samplesPerPixel == 64);
    CHECK(finished.complete);
}

TEST_CASE("A checkpoint that does not fit the render is refused", "[render][checkpoint]") {
    const std::string xml = checkpointScene(
        R"(<integrator type="path_mis"/>)",
        R"(<sampler type="independent"><integer name="sampleCount" value="8"/></sampler>)");
    std::vector<std::string> states;
    renderWithCheckpoints(xml, &states);
    REQUIRE(!states.empty());
    // Cut short anywhere: "truncated", never a crash.
    for (const size_t length : {size_t(0), size_t(7), states[0].size() / 2, states[0].size() - 1}) {
        const std::string truncated = states[0].substr(0, length);
        CHECK_THAT(errorOf([&] { renderWithCheckpoints(xml, nullptr, &truncated); }),
                   Catch::Contains("truncated"));
    }
    // Of another image size.
    std::string resized = xml;
    resized.replace(resized.find("value=\"24\""), 10, "value=\"20\"");
    CHECK_THAT(errorOf([&] { renderWithCheckpoints(resized, nullptr, &states[0]); }),
               Catch::Contains("does not fit this render"));
}

TEST_CASE("Checkpoint files name what they are of, and refuse anything else", "[checkpoint]") {
    CheckpointIdentity identity;
    identity.version = "1.2.3";
    identity.sceneHash = "00112233aabbccdd";
    identity.options = {{"--spp", "64"}, {"--aovs", "albedo"}, {"--part", ""}};
    const std::string bytes = encodeCheckpoint(identity, "the state");
    CHECK(decodeCheckpoint(bytes, "a.checkpoint", identity) == "the state");

    CheckpointIdentity other = identity;
    other.version = "1.2.4";
    CHECK_THAT(errorOf([&] { decodeCheckpoint(bytes, "a.checkpoint", other); }),
               Catch::Contains("written by nori 1.2.3") && Catch::Contains("this is nori 1.2.4"));
    other = identity;
    other.sceneHash = "ffffffffffffffff";
    CHECK_THAT(errorOf([&] { decodeCheckpoint(bytes, "a.checkpoint", other); }),
               Catch::Contains("of another scene"));
    other = identity;
    other.options[0].second = "128";
    CHECK_THAT(errorOf([&] { decodeCheckpoint(bytes, "a.checkpoint", other); }),
               Catch::Contains("rendered with --spp 64, this render has 128"));
    CHECK_THAT(errorOf([&] { decodeCheckpoint("an EXR, say", "b.exr", identity); }),
               Catch::Contains("'b.exr' is not a nori checkpoint"));
    for (size_t length = 30; length < bytes.size(); length += 7)
        CHECK_THAT(errorOf([&] { decodeCheckpoint(bytes.substr(0, length), "c", identity); }),
                   Catch::Contains("truncated") || Catch::Contains("corrupt"));
}

TEST_CASE("nori killed at random moments and resumed writes the uninterrupted EXR",
          "[cli][checkpoint]") {
    const TempDir dir;
    struct Config {
        std::string name, xml;
        std::vector<std::string> flags;
    };
    const std::string spp =
        R"(<sampler type="independent"><integer name="sampleCount" value="512"/></sampler>)";
    const std::vector<Config> configs = {
        {"path_mis", checkpointScene(R"(<integrator type="path_mis"/>)", spp), {}},
        {"volpath",
         checkpointScene(R"(<integrator type="volpath"/>)", spp,
                         R"(<medium type="homogeneous" id="fog">
                                <color name="sigmaS" value="0.3"/><color name="sigmaA" value="0.05"/>
                            </medium>
                            <mesh type="sphere"><float name="radius" value="10"/>
                                <ref name="interior" id="fog"/><bsdf type="null"/></mesh>)"),
         {}},
        {"bdpt", checkpointScene(R"(<integrator type="bdpt"/>)", spp), {}},
        {"progressive photon mapper",
         checkpointScene(R"(<integrator type="progressivephotonmapper">
                                <integer name="photonCount" value="20000"/></integrator>)",
                         R"(<sampler type="independent"><integer name="sampleCount" value="24"/>
                            </sampler>)"),
         {}},
        {"adaptive sampling",
         checkpointScene(R"(<integrator type="path_mis"/>)",
                         R"(<sampler type="independent"><integer name="sampleCount" value="512"/>
                                <float name="maxTolerance" value="0.05"/>
                                <integer name="minSamples" value="8"/></sampler>)"),
         {}},
        {"part 2 of 3",
         checkpointScene(R"(<integrator type="path_mis"/>)", spp),
         {"--part", "2/3"}},
    };
    // 20 moments over the six renders, drawn with a fixed seed within each render's own
    // duration (and a little past it: the final write); the first of each render's comes
    // before its first checkpoint.
    PCG32 random(77, 1);
    std::vector<double> durations;
    std::vector<LayeredImage> references;
    for (size_t c = 0; c < configs.size(); ++c) {
        const std::string scene = dir.write(fmt::format("scene{}.xml", c), configs[c].xml);
        std::vector<std::string> arguments = {
            scene,          "--no-progress",
            "--checkpoint", "off",
            "-o",           (dir.path() / fmt::format("reference{}", c)).string()};
        arguments.insert(arguments.end(), configs[c].flags.begin(), configs[c].flags.end());
        const auto start = std::chrono::steady_clock::now();
        const ProcessResult result = runNori(arguments);
        durations.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        INFO(result.output);
        REQUIRE(result.exitCode == 0);
        references.push_back(
            LayeredImage::loadEXR((dir.path() / fmt::format("reference{}.exr", c)).string()));
    }
    int resumedRuns = 0;
    for (int moment = 0; moment < 20; ++moment) {
        const size_t c = static_cast<size_t>(moment) % configs.size();
        const double fraction = moment < 6 ? 0.05 : 1.1 * random.nextFloat();
        const double seconds = fraction * durations[c];
        INFO(configs[c].name << ", killed after " << seconds << " s of " << durations[c]);
        const std::string stem = (dir.path() / fmt::format("run{}", moment)).string();
        std::vector<std::string> arguments = {dir.path() / fmt::format("scene{}.xml", c),
                                              "--no-progress",
                                              "--checkpoint",
                                              "0",
                                              "-o",
                                              stem};
        arguments.insert(arguments.end(), configs[c].flags.begin(), configs[c].flags.end());
        const ProcessResult killed = runNoriKilledAfter(arguments, seconds);
        INFO(killed.output);
        if (killed.exitCode != 0) {
            REQUIRE(killed.exitCode == 128 + SIGKILL);
            // Resumed from its checkpoint; killed before the first one, started over.
            const bool hasCheckpoint = fs::exists(stem + ".checkpoint");
            std::vector<std::string> again = arguments;
            if (hasCheckpoint)
                again.push_back("--resume");
            const ProcessResult resumed = runNori(again);
            INFO(resumed.output);
            REQUIRE(resumed.exitCode == 0);
            if (hasCheckpoint) {
                CHECK_THAT(resumed.output, Catch::Contains("Resumed from"));
                ++resumedRuns;
            }
        }
        CHECK_FALSE(fs::exists(stem + ".checkpoint")); // a complete render removes it
        CHECK(identicalLayers(references[c], LayeredImage::loadEXR(stem + ".exr")));
    }
    // Most moments fall within a render, after its first checkpoint (how many depends on
    // the machine's timing).
    INFO(resumedRuns << " of 20 runs resumed from a checkpoint");
    CHECK(resumedRuns >= 6);
}

TEST_CASE("nori --resume refuses a checkpoint of another scene, version or a truncated one",
          "[cli][checkpoint]") {
    const TempDir dir;
    // The light's radiance a variable, so that -D changes the scene.
    std::string xml = checkpointScene(
        R"(<integrator type="path_mis"/>)",
        R"(<sampler type="independent"><integer name="sampleCount" value="65536"/></sampler>)");
    xml.replace(xml.find(R"(value="20")"), 10, R"(value="$light")");
    xml.replace(0, 7, R"(<scene><default name="light" value="20"/>)");
    const std::string scene = dir.write("scene.xml", xml);
    const std::string stem = (dir.path() / "out").string();
    // No checkpoint yet.
    ProcessResult result = runNori({scene, "--no-progress", "-o", stem, "--resume"});
    CHECK(result.exitCode != 0);
    CHECK_THAT(result.output,
               Catch::Contains("there is no checkpoint") && Catch::Contains("out.checkpoint"));
    // A checkpoint: killed after its first passes (of a render of some 20 s).
    result = runNoriKilledAfter({scene, "--no-progress", "-o", stem, "--checkpoint", "0"}, 1.0);
    INFO(result.output);
    REQUIRE(result.exitCode == 128 + SIGKILL);
    REQUIRE(fs::exists(stem + ".checkpoint"));
    const std::string bytes = readBinaryFile(stem + ".checkpoint", "test");
    // Another scene (a -D definition changed what it renders), another option.
    result = runNori({scene, "--no-progress", "-o", stem, "--resume", "-D", "light=21"});
    CHECK(result.exitCode != 0);
    CHECK_THAT(result.output, Catch::Contains("of another scene"));
    result = runNori({scene, "--no-progress", "-o", stem, "--resume", "--spp", "32"});
    CHECK(result.exitCode != 0);
    CHECK_THAT(result.output, Catch::Contains("rendered with --spp (none), this render has 32"));
    // Truncated.
    writeBinaryFile(stem + ".checkpoint", bytes.substr(0, bytes.size() / 2), "test");
    result = runNori({scene, "--no-progress", "-o", stem, "--resume"});
    CHECK(result.exitCode != 0);
    CHECK_THAT(result.output, Catch::Contains("truncated"));
    // Of another version: its version string edited.
    std::string edited = bytes;
    const size_t at = edited.find(NORI_VERSION);
    REQUIRE(at != std::string::npos);
    edited[at] = edited[at] == '9' ? '8' : '9';
    writeBinaryFile(stem + ".checkpoint", edited, "test");
    result = runNori({scene, "--no-progress", "-o", stem, "--resume"});
    CHECK(result.exitCode != 0);
    CHECK_THAT(result.output, Catch::Contains("was written by nori"));
    // Without --resume the render starts over (here with fewer samples), and removes the
    // checkpoint when done.
    result = runNori({scene, "--no-progress", "-o", stem, "--spp", "64"});
    CHECK(result.exitCode == 0);
    CHECK_FALSE(fs::exists(stem + ".checkpoint"));
}
