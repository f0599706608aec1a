// warptest: the χ² test of one sampling routine from the command line, with a picture of
// the observed and expected histograms and their difference, so a student can see where
// a sampler goes wrong.
#include "app/cli.h"
#include <nori/bsdf.h>
#include <nori/emitter.h>
#include <nori/parser.h>
#include <nori/phase.h>
#include <nori/samplingroutines.h>
#include <nori/strutil.h>

#include <filesystem>
#include <iostream>
#include <optional>

using namespace nori;

namespace {

const char *kDescription = R"(The χ² test of one sampling routine, with a picture: WHAT is one of
  WARP                   a warp of warp.h (see --list), e.g. cosine_hemisphere, beckmann
  bsdf XML               a BSDF, as an XML snippet or file, e.g. '<bsdf type="diffuse"/>'
  phase XML              a phase function, e.g. '<phase type="hg"><float name="g" value="0.5"/></phase>'
  emitter XML            an emitter (direction sampling seen from --ref))";

const char *kFooter = R"(
Writes DIR/warptest-<what>_<parameters>_<angle>.png (observed | expected | difference:
named after what was tested, so runs do not overwrite each other), prints the p-value and
the verdict, and exits 0 when the test passes, 1 when it fails.)";

/// What the command line gives.
struct Arguments {
    std::vector<std::string> positional;
    std::optional<float> parameter;
    float angle = 30.0f;
    std::vector<float> ref{0.0f, 0.0f, 0.0f};
    std::string outDir = ".";
    bool list = false;
    ChiSquareOptions options;
};

std::shared_ptr<NoriObject> loadObject(const std::string &xmlOrFile) {
    // XML text starts with '<'; anything else names a file.
    const size_t start = xmlOrFile.find_first_not_of(" \t\r\n");
    if (start != std::string::npos && xmlOrFile[start] == '<')
        return loadFromXMLString(xmlOrFile);
    return loadFromXML(xmlOrFile);
}

template <typename T>
std::shared_ptr<T> loadAs(const std::string &xmlOrFile, NoriObject::EClassType type) {
    std::shared_ptr<NoriObject> object = loadObject(xmlOrFile);
    if (object->getClassType() != type)
        throw NoriException("expected a <{}>, got a <{}>", NoriObject::classTypeName(type),
                            NoriObject::classTypeName(object->getClassType()));
    return std::static_pointer_cast<T>(object);
}

int run(Arguments &arguments) {
    // A user's plugin that registers one of our names replaces ours here too.
    NoriObjectFactory::checkRegistry();
    if (arguments.list) {
        for (const NamedWarp &warp : namedWarps())
            std::cout << warp.name
                      << (warp.parameterName.empty()
                              ? ""
                              : fmt::format(" (--param {}, default {})", warp.parameterName,
                                            warp.defaultParameter))
                      << "\n";
        return 0;
    }
    const std::vector<std::string> &positional = arguments.positional;
    const std::optional<float> &parameter = arguments.parameter;
    const float angle = arguments.angle;
    const std::string &outDir = arguments.outDir;
    ChiSquareOptions &options = arguments.options;
    if (arguments.ref.size() != 3)
        throw NoriException("--ref needs three numbers x,y,z");
    const Point3f ref(arguments.ref[0], arguments.ref[1], arguments.ref[2]);
    if (positional.empty())
        throw NoriException("nothing to test (see warptest --help)");
    options.validate();

    // Keep the plugin alive while its routine runs.
    std::shared_ptr<NoriObject> plugin;
    SamplingRoutine routine;
    std::string name, title; // name: of the picture, after what was tested and how
    const float theta = degToRad(angle);
    const Vector3f wi(std::sin(theta), 0.0f, std::cos(theta));
    const std::string &what = positional[0];
    if (what == "bsdf" || what == "phase" || what == "emitter") {
        if (positional.size() != 2)
            throw NoriException("'{}' needs one XML snippet or file", what);
        if (what == "bsdf") {
            auto bsdf = loadAs<BSDF>(positional[1], NoriObject::EBSDF);
            routine = bsdfRoutine(*bsdf, wi);
            title = fmt::format("{} at {} deg", bsdf->toString(), angle);
            plugin = bsdf;
            name = chiSquarePictureName("bsdf-" + bsdf->pluginName(), parameterSetOf(*bsdf),
                                        fmt::format("{}deg", angle));
        } else if (what == "phase") {
            auto phase = loadAs<PhaseFunction>(positional[1], NoriObject::EPhaseFunction);
            routine = phaseRoutine(*phase, wi);
            title = fmt::format("{} at {} deg", phase->toString(), angle);
            plugin = phase;
            name = chiSquarePictureName("phase-" + phase->pluginName(), parameterSetOf(*phase),
                                        fmt::format("{}deg", angle));
        } else {
            auto emitter = loadAs<Emitter>(positional[1], NoriObject::EEmitter);
            if (emitter->isDelta())
                throw NoriException("{} is a delta light: it has no density to test",
                                    emitter->toString());
            routine = emitterRoutine(*emitter, ref);
            title =
                fmt::format("{} from ({}, {}, {})", emitter->toString(), ref.x(), ref.y(), ref.z());
            plugin = emitter;
            name =
                chiSquarePictureName("emitter-" + emitter->pluginName(), parameterSetOf(*emitter),
                                     fmt::format("ref-{}-{}-{}", ref.x(), ref.y(), ref.z()));
        }
    } else {
        if (positional.size() != 1)
            throw NoriException("unexpected argument '{}'", positional[1]);
        const NamedWarp &warp = findWarp(what);
        const float p = parameter.value_or(warp.defaultParameter);
        routine = warp.routine(p);
        name = chiSquarePictureName(
            warp.name,
            warp.parameterName.empty() ? "" : fmt::format("{}={}", warp.parameterName, p), "");
        title = warp.parameterName.empty()
                    ? warp.name
                    : fmt::format("{} ({} = {})", warp.name, warp.parameterName, p);
    }

    const ChiSquareReport report = runChiSquareTest(routine, options);
    std::filesystem::create_directories(outDir);
    const std::string picture =
        (std::filesystem::path(outDir) / ("warptest-" + name + ".png")).string();
    renderChiSquareReport(report, title).savePNG(picture);
    std::cout << title << ": " << report.result.message << "\n";
    std::cout << "p-value " << report.result.pValue << "\n";
    std::cout << "verdict " << (report.result.passed ? "pass" : "fail") << "\n";
    std::cout << "picture " << picture << "\n";
    return report.result.passed ? 0 : 1;
}

} // namespace

int main(int argc, char **argv) {
    Arguments arguments;
    return runCommandLine(
        argc, argv, "warptest", kDescription,
        [&](CLI::App &app) {
            app.footer(kFooter);
            app.add_option("what", arguments.positional, "what to test, and its XML")
                ->type_name("WHAT [XML]");
            app.add_option("--param", arguments.parameter,
                           "the warp's parameter (alpha, g, cosThetaMax)")
                ->type_name("V");
            app.add_option("--angle", arguments.angle,
                           "incident angle from the normal for bsdf/phase (default 30)")
                ->type_name("DEG");
            app.add_option("--ref", arguments.ref, "reference point for emitters (default 0,0,0)")
                ->type_name("x,y,z")
                ->delimiter(',')
                ->expected(3);
            app.add_option("--resolution", arguments.options.resolution,
                           "histogram bins along cos(theta) or x (default 10)")
                ->type_name("N");
            app.add_option("--samples", arguments.options.sampleCount,
                           "number of samples (default 5000 per bin)")
                ->type_name("N");
            app.add_option("--significance", arguments.options.significanceLevel,
                           "significance level (default 0.01)")
                ->type_name("A");
            app.add_option("--seed", arguments.options.seed,
                           "seed of the uniform samples (default 0)")
                ->type_name("S");
            app.add_option("--out", arguments.outDir, "folder for the picture (default .)")
                ->type_name("DIR");
            app.add_flag("--list", arguments.list, "list the warps");
        },
        [&](const CLI::App &) { return run(arguments); }, 2);
}
