// nori-bench-samplers: the figures of the progressive render loop and the samplers.
//   1. MSE at 16 and 64 spp against a reference of ANOTHER estimator (the independent
//      sampler at --reference-spp, 64× the larger count by default, so that no sampler
//      shares the reference's sample pattern), on the Cornell box with a diffuse and with
//      a glass sphere (scenes/cbox/cbox.xml), path tracing (path_mis): independent,
//      stratified and sobol, as ratios to independent with their spread over seeds. The
//      reference's own error (MSE of independent at n spp × n / reference spp, for
//      independent samples) is subtracted from every MSE before the ratio.
//   2. The time overhead of passes (1, 1, 2, ..., 64 spp) over rendering each block at
//      its full sample count in one pass (the loop before passes), best of 3.
//   3. Adaptive sampling against 64 spp everywhere at equal time (the adaptive render
//      gets the uniform one's time), relMSE against the independent reference, on three
//      scenes (the two boxes and Veach's glossy plates), as ratios per seed with their
//      spread; and its bias on a white furnace with a known answer (a t-test over
//      independent pixels).
//   4. What a sampler costs: nanoseconds per next2D() alone (one thread, 64 dimensions
//      per sample), and the render time of the diffuse box at 64 spp with each sampler
//      (path_mis: the same number of rays on average), rounds alternating the samplers,
//      median and spread, and each sampler's ratio to independent in the same round.
//
//   nori-bench-samplers [--size N] [--reference-spp N] [--seeds N] [--threads N]
//                       [--section samplers|overhead|adaptive|bias|cost]
#include "app/cli.h"
#include <nori/bitmap.h>
#include <nori/filesystem.h>
#include <nori/parser.h>
#include <nori/proplist.h>
#include <nori/render.h>
#include <nori/sampler.h>
#include <nori/scene.h>
#include <nori/statistics.h>
#include <nori/strutil.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>

using namespace nori;

namespace {

struct Settings {
    int size = 128, referenceSpp = 4096, seeds = 8, threads = 0;
    std::string section; ///< empty: every section
};

/// The Cornell box, its sphere diffuse unless `defines` says otherwise.
std::shared_ptr<Scene> cornellBox(const Settings &settings, Defines defines) {
    defines["size"] = std::to_string(settings.size);
    defines.emplace("integrator", "path_mis");
    defines.emplace("sphere", "diffuse");
    return std::dynamic_pointer_cast<Scene>(
        loadFromXML(std::string(NORI_SOURCE_DIR) + "/scenes/cbox/cbox.xml", LoadOptions(defines)));
}

RenderResult render(Scene &scene, const Settings &settings, RenderOptions options = {}) {
    options.threads = settings.threads;
    return renderScene(scene, options);
}

RenderResult renderBox(const Settings &settings, const Defines &defines) {
    return render(*cornellBox(settings, defines), settings);
}

void samplerFigures(const Settings &settings) {
    const std::vector<std::string> samplers = {"independent", "stratified", "sobol"};
    for (const std::string sphere : {"diffuse", "dielectric"}) {
        const RenderResult reference =
            renderBox(settings, {{"integrator", "path_mis"},
                                 {"sphere", sphere},
                                 {"sampler", "independent"},
                                 {"spp", std::to_string(settings.referenceSpp)}});
        std::cout << fmt::format("path_mis, {} sphere: reference {}x{} at {} spp (independent, "
                                 "seed 0) in {:.1f} s\n",
                                 sphere, settings.size, settings.size, settings.referenceSpp,
                                 reference.seconds);
        for (int spp : {16, 64}) {
            // mse[sampler][seed], seeds 1..n.
            std::vector<std::vector<double>> mse(samplers.size());
            for (size_t k = 0; k < samplers.size(); ++k)
                for (int seed = 1; seed <= settings.seeds; ++seed)
                    mse[k].push_back(
                        meanSquaredError(renderBox(settings, {{"integrator", "path_mis"},
                                                              {"sphere", sphere},
                                                              {"sampler", samplers[k]},
                                                              {"spp", std::to_string(spp)},
                                                              {"seed", std::to_string(seed)}})
                                             .image,
                                         reference.image));
            // The reference's error, from independent's own at spp: E[MSE] = σ²/spp + σ²/ref.
            RunningMoments independent;
            for (double value : mse[0])
                independent.add(value);
            const double referenceError =
                independent.mean * spp / (settings.referenceSpp + double(spp));
            std::string line = fmt::format("  {:>3} spp  independent MSE {:.3e} (reference's "
                                           "share {:.1f} %)",
                                           spp, independent.mean - referenceError,
                                           100.0 * referenceError / independent.mean);
            for (size_t k = 1; k < samplers.size(); ++k) {
                // The ratio per seed (paired: seed s of both samplers), then its spread.
                RunningMoments ratios;
                for (size_t s = 0; s < mse[k].size(); ++s)
                    ratios.add((mse[k][s] - referenceError) / (mse[0][s] - referenceError));
                line +=
                    fmt::format("  {} {:.3f}x ± {:.3f} (sd {:.3f}, {} seeds)", samplers[k],
                                ratios.mean, std::sqrt(ratios.variance() / double(ratios.count)),
                                std::sqrt(ratios.variance()), ratios.count);
            }
            std::cout << line << "\n";
        }
    }
}

void passOverheadFigures(const Settings &settings) {
    auto scene = cornellBox(settings, {{"integrator", "path_mis"}, {"spp", "64"}});
    double passes = 1e30, onePass = 1e30;
    for (int run = 0; run < 3; ++run) {
        passes = std::min(passes, render(*scene, settings).seconds);
        RenderOptions whole;
        whole.minPassSamples = whole.maxPassSamples = 64;
        onePass = std::min(onePass, render(*scene, settings, whole).seconds);
    }
    std::cout << fmt::format("path_mis, 64 spp, {}x{}: passes 1, 1, 2, ..., 32: {:.3f} s; one "
                             "pass: {:.3f} s; overhead {:+.1f}%\n",
                             settings.size, settings.size, passes, onePass,
                             100.0 * (passes / onePass - 1.0));
}

void adaptiveFigures(const Settings &settings) {
    struct BenchScene {
        std::string name, file;
        Defines defines;
    };
    const std::string size = std::to_string(settings.size);
    const std::vector<BenchScene> scenes = {
        {"Cornell box, diffuse sphere", "cbox/cbox.xml", {{"size", size}, {"sphere", "diffuse"}}},
        {"Cornell box, glass sphere", "cbox/cbox.xml", {{"size", size}, {"sphere", "dielectric"}}},
        {"Veach's glossy plates",
         "veach/veach.xml",
         {{"width", size},
          {"height", std::to_string(settings.size * 3 / 5)},
          {"integrator", "path_mis"}}}};
    const std::vector<std::string> tolerances = {"0.02", "0.05", "0.1"};
    for (const BenchScene &benchScene : scenes) {
        auto load = [&](Defines defines) {
            for (const auto &[name, value] : benchScene.defines)
                defines.emplace(name, value);
            return std::dynamic_pointer_cast<Scene>(loadFromXML(
                std::string(NORI_SOURCE_DIR) + "/scenes/" + benchScene.file, LoadOptions(defines)));
        };
        const RenderResult reference = render(
            *load({{"spp", std::to_string(settings.referenceSpp)}, {"seed", "0"}}), settings);
        // Adaptive sampling reconstructs pixels by filter importance sampling, which keeps
        // the noise of neighbouring pixels apart: the uniform renders do too.
        RenderOptions filterSampled;
        filterSampled.filterImportanceSampling = true;
        RunningMoments uniformError, uniformSeconds;
        std::vector<RunningMoments> ratios(tolerances.size()), spp(tolerances.size());
        std::vector<double> uniformErrors;
        std::vector<std::vector<double>> adaptiveErrors(tolerances.size());
        for (int seed = 1; seed <= settings.seeds; ++seed) {
            const RenderResult uniform = render(
                *load({{"spp", "64"}, {"seed", std::to_string(seed)}}), settings, filterSampled);
            uniformErrors.push_back(relativeMeanSquaredError(uniform.image, reference.image));
            uniformSeconds.add(uniform.seconds);
            for (size_t k = 0; k < tolerances.size(); ++k) {
                // At most 4096 spp, within the time the uniform render took.
                RenderOptions options = filterSampled;
                options.timeBudget = uniform.seconds;
                const RenderResult adaptive = render(*load({{"spp", "4096"},
                                                            {"tolerance", tolerances[k]},
                                                            {"seed", std::to_string(seed)}}),
                                                     settings, options);
                adaptiveErrors[k].push_back(
                    relativeMeanSquaredError(adaptive.image, reference.image));
                spp[k].add(double(adaptive.samplesTaken) / double(adaptive.image.size()));
            }
        }
        // The reference's share of every relMSE, from uniform's own at 64 spp (independent
        // samples: E[relMSE] ≈ e/64 + e/reference), taken out before the ratios.
        for (double value : uniformErrors)
            uniformError.add(value);
        const double referenceError = uniformError.mean * 64.0 / (settings.referenceSpp + 64.0);
        std::string lines = fmt::format(
            "adaptive sampling at equal time, {} ({}, path_mis, reference {} spp in {:.1f} s): "
            "64 spp everywhere in {:.2f} s: relMSE {:.3e} (reference's share {:.1f} %)\n",
            benchScene.name, benchScene.file, settings.referenceSpp, reference.seconds,
            uniformSeconds.mean, uniformError.mean - referenceError,
            100.0 * referenceError / uniformError.mean);
        for (size_t k = 0; k < tolerances.size(); ++k) {
            // The ratio per seed (paired: seed s of both), then its spread.
            for (size_t s = 0; s < uniformErrors.size(); ++s)
                ratios[k].add((adaptiveErrors[k][s] - referenceError) /
                              (uniformErrors[s] - referenceError));
            lines += fmt::format("  maxTolerance {}: {:.1f} spp on average; relMSE {:.3f}x of "
                                 "uniform ± {:.3f} (sd {:.3f}, {} seeds)\n",
                                 tolerances[k], spp[k].mean, ratios[k].mean,
                                 std::sqrt(ratios[k].variance() / double(ratios[k].count)),
                                 std::sqrt(ratios[k].variance()), ratios[k].count);
        }
        std::cout << lines << std::flush;
    }
}

/// Inside a closed box of albedo 0.6 emitting 0.4, every pixel sees Le/(1 − a) = 1: the
/// bias of adaptive sampling as a t-test over 64 × 64 independent pixels (box filter).
void adaptiveBiasFigures(const Settings &settings) {
    const std::filesystem::path box = std::filesystem::temp_directory_path() / "nori-furnace.obj";
    writeBinaryFile(box.string(),
                    "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\n"
                    "v 1 1 1\nv -1 1 1\nf 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 4 3 7 8\n"
                    "f 1 4 8 5\nf 2 6 7 3\n",
                    "mesh");
    for (const char *tolerance : {"0", "0.1", "0.3"}) {
        auto scene = std::dynamic_pointer_cast<Scene>(loadFromXMLString(fmt::format(
            R"(<scene><integrator type="path_mis"/>
            <sampler type="independent"><integer name="sampleCount" value="256"/>
                <float name="maxTolerance" value="{}"/></sampler>
            <camera type="perspective"><integer name="width" value="64"/>
                <integer name="height" value="64"/><rfilter type="box"/></camera>
            <mesh type="obj"><string name="filename" value="{}"/>
                <bsdf type="diffuse"><color name="albedo" value="0.6"/></bsdf>
                <emitter type="area"><color name="radiance" value="0.4"/></emitter></mesh>
            </scene>)",
            tolerance, box.string())));
        const RenderResult result = render(*scene, settings);
        RunningMoments pixels;
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x)
                pixels.add(result.image(y, x).r());
        const StudentTResult test =
            studentTTest(pixels.mean, pixels.variance(), pixels.count, 1.0, 0.01);
        std::cout << fmt::format("furnace, maxTolerance {} (minSamples 16, at most 256 spp): "
                                 "{:.1f} spp on average, mean {:.5f} (bias {:+.2f}%), t = {:.2f}: "
                                 "{}\n",
                                 tolerance, double(result.samplesTaken) / (64 * 64), pixels.mean,
                                 100.0 * (pixels.mean - 1.0), test.t,
                                 test.passed ? "no bias detected" : "biased");
    }
    std::filesystem::remove(box);
}

/// The median of `values` (a copy is sorted).
double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    const size_t n = values.size();
    return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

void samplerCostFigures(const Settings &settings) {
    const std::vector<std::string> samplers = {"independent", "stratified", "sobol"};
    constexpr int kRounds = 5;
    for (const std::string &name : samplers) {
        PropertyList props;
        props.setInteger("sampleCount", 64);
        auto sampler = std::dynamic_pointer_cast<Sampler>(
            NoriObjectFactory::createInstance(name, NoriObject::ESampler, props));
        double best = 1e30, sink = 0.0;
        constexpr int kPixels = 4096, kSamples = 64, kDimensions = 64;
        for (int round = 0; round < kRounds; ++round) {
            const auto start = std::chrono::steady_clock::now();
            for (int pixel = 0; pixel < kPixels; ++pixel)
                for (int sample = 0; sample < kSamples; ++sample) {
                    sampler->generate(Point2i(pixel % 64, pixel / 64), sample);
                    for (int d = 0; d < kDimensions; ++d) {
                        const Point2f u = sampler->next2D();
                        sink += u.x() + u.y();
                    }
                }
            const double seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            best = std::min(best, seconds);
        }
        std::cout << fmt::format("{:<12} next2D(): {:.1f} ns (best of {}, one thread; checksum "
                                 "{:.0f})\n",
                                 name, 1e9 * best / (double(kPixels) * kSamples * kDimensions),
                                 kRounds, sink);
    }
    // seconds[sampler][round]
    std::vector<std::vector<double>> seconds(samplers.size());
    for (int round = 0; round < kRounds; ++round)
        for (size_t k = 0; k < samplers.size(); ++k)
            seconds[k].push_back(
                renderBox(settings,
                          {{"integrator", "path_mis"}, {"sampler", samplers[k]}, {"spp", "64"}})
                    .seconds);
    for (size_t k = 0; k < samplers.size(); ++k) {
        std::vector<double> ratios;
        ratios.reserve(kRounds);
        for (int round = 0; round < kRounds; ++round)
            ratios.push_back(seconds[k][round] / seconds[0][round]);
        const auto [low, high] = std::minmax_element(ratios.begin(), ratios.end());
        std::cout << fmt::format("path_mis, diffuse box {}x{}, 64 spp, {:<12}: median {:.2f} s "
                                 "(range {:.2f}-{:.2f}); to independent {:.3f}x (range "
                                 "{:.3f}-{:.3f}, {} rounds)\n",
                                 settings.size, settings.size, samplers[k], median(seconds[k]),
                                 *std::min_element(seconds[k].begin(), seconds[k].end()),
                                 *std::max_element(seconds[k].begin(), seconds[k].end()),
                                 median(ratios), *low, *high, kRounds);
    }
}

int run(const Settings &settings) {
    const std::vector<std::pair<std::string, void (*)(const Settings &)>> sections = {
        {"samplers", samplerFigures},
        {"overhead", passOverheadFigures},
        {"adaptive", adaptiveFigures},
        {"bias", adaptiveBiasFigures},
        {"cost", samplerCostFigures}};
    for (const auto &[name, figures] : sections)
        if (settings.section.empty() || settings.section == name)
            figures(settings);
    return 0;
}

} // namespace

int main(int argc, char **argv) {
    Settings settings;
    return runCommandLine(
        argc, argv, "nori-bench-samplers",
        "The figures of the samplers and the progressive loop: MSE per sampler, the pass "
        "overhead, adaptive sampling, what each sampler costs.",
        [&](CLI::App &app) {
            app.add_option("--size", settings.size, "image size")
                ->type_name("N")
                ->check(CLI::PositiveNumber);
            app.add_option("--reference-spp", settings.referenceSpp, "of the reference")
                ->type_name("N")
                ->check(CLI::PositiveNumber);
            app.add_option("--seeds", settings.seeds, "seeds averaged over")
                ->type_name("N")
                ->check(CLI::PositiveNumber);
            app.add_option("--threads", settings.threads, "threads")
                ->type_name("N")
                ->check(CLI::PositiveNumber);
            app.add_option("--section", settings.section, "only these figures")
                ->type_name("NAME")
                ->check(CLI::IsMember({"samplers", "overhead", "adaptive", "bias", "cost"}));
        },
        [&](const CLI::App &) { return run(settings); });
}
