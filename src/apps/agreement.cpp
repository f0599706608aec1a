// nori-agreement: the agreement matrix. Renders the battery of src/testing/agreementscenes
// with every integrator and sampler that applies, compares the means of image regions
// between every two estimators in standard errors, prints the table, and exits with 1
// when a comparison disagrees (with --require-power, also when one lacks the power to see
// a 0.5 % bias).
#include "app/cli.h"
#include "testing/agreementscenes.h"
#include <nori/common.h>
#include <nori/testsamples.h>

#include <cstdio>

using namespace nori;

namespace {

struct Options {
    bool soak = false, requirePower = false;
    std::vector<std::string> scenes, estimators;
    int threads = 0, batches = 16;
    uint64_t seed = 1;
    std::string pictures;
};

int run(const Options &options) {
    std::vector<AgreementScene> scenes = agreementMatrixScenes();
    if (!options.scenes.empty()) {
        std::vector<AgreementScene> chosen;
        for (const std::string &name : options.scenes) {
            const auto found =
                std::find_if(scenes.begin(), scenes.end(),
                             [&](const AgreementScene &s) { return s.name == name; });
            if (found == scenes.end()) {
                std::string names;
                for (const AgreementScene &s : scenes)
                    names += (names.empty() ? "" : ", ") + s.name;
                throw NoriException("--scene: no scene '{}' (the scenes: {})", name, names);
            }
            chosen.push_back(*found);
        }
        scenes = std::move(chosen);
    }
    if (!options.estimators.empty())
        for (AgreementScene &scene : scenes) {
            // The reference stays: the table compares with it.
            std::vector<Estimator> kept{scene.estimators.front()};
            for (size_t e = 1; e < scene.estimators.size(); ++e)
                if (std::find(options.estimators.begin(), options.estimators.end(),
                              scene.estimators[e].label) != options.estimators.end())
                    kept.push_back(scene.estimators[e]);
            scene.estimators = std::move(kept);
        }
    AgreementSettings settings;
    settings.threads = options.threads;
    settings.batches = options.batches;
    settings.seed = options.seed;
    settings.pictureFolder = options.pictures;
    // Soak: 8 times the samples, so that biases of a quarter of the size are seen.
    if (options.soak) {
        settings.sampleScale = 8.0;
        settings.detectableBias = 0.005 / std::sqrt(8.0);
    }
    settings.progress = [](const std::string &line) { std::fprintf(stderr, "%s\n", line.c_str()); };
    std::printf("%s", testSampleScaleNotice().c_str());
    const AgreementReport report = runAgreement(scenes, settings);
    std::printf("%s", report.table(scenes, settings).c_str());
    const bool passed = report.passed(options.requirePower);
    std::printf("verdict: %s (%s)\n", passed ? "pass" : "FAIL",
                options.requirePower ? "agreement and power" : "agreement; power reported");
    return passed ? 0 : 1;
}

} // namespace

int main(int argc, char **argv) {
    Options options;
    return runCommandLine(
        argc, argv, "nori-agreement",
        "The agreement matrix: every integrator and sampler on a battery of small scenes, "
        "the means of image regions compared in standard errors (from independent batches "
        "of each estimator). Fails when two estimators differ by more than 4 standard "
        "errors (with --require-power, also when a comparison could not see a 0.5 % bias).",
        [&](CLI::App &app) {
            app.add_flag("--soak", options.soak,
                         "8 times the samples: sees biases of 0.18 %, for benchmarks");
            app.add_flag("--require-power", options.requirePower,
                         "also fail when a comparison cannot see a 0.5 % bias");
            app.add_option("--scene", options.scenes, "only these scenes (repeatable)")
                ->type_name("NAME");
            app.add_option("--estimator", options.estimators,
                           "only these estimators besides each scene's reference (repeatable; "
                           "labels as the table prints them)")
                ->type_name("LABEL");
            app.add_option("--threads", options.threads, "worker threads (default: all cores)")
                ->type_name("N");
            app.add_option("--batches", options.batches,
                           "independent renders per estimator (default 16)")
                ->type_name("N");
            app.add_option("--seed", options.seed, "the first seed (default 1)")->type_name("S");
            app.add_option("--pictures", options.pictures,
                           "write each estimator's mean image to this folder")
                ->type_name("DIR");
        },
        [&](const CLI::App &) { return run(options); });
}
