// The `nori` program: renders a scene file to EXR + PNG, or runs a test file.
#include "app/buildinfo.h"
#include "app/checkpoint.h"
#include "app/cli.h"
#include "app/plugincatalog.h"
#include "app/preview.h"
#include "app/program.h"
#include "app/progress.h"
#include "app/renderpart.h"
#include "denoise/denoiser.h"
#include "testing/integratortest.h"
#include "testing/plugintest.h"
#include <nori/aov.h>
#include <nori/filesystem.h>
#include <nori/mitsubaimport.h>
#include <nori/parser.h>
#include <nori/pbrtimport.h>
#include <nori/plugindoc.h>
#include <nori/render.h>
#include <nori/scene.h>
#include <nori/statistics.h>
#include <nori/strutil.h>
#include <nori/test.h>
#include <nori/testsamples.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <optional>
#include <set>
#include <signal.h>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace nori;

namespace {

/// Exit status after SIGINT, as a shell reports a process killed by it.
constexpr int kExitInterrupted = 128 + SIGINT;

std::atomic<bool> g_interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the SIGINT flag must be signal-safe");

extern "C" void onInterrupt(int) {
    g_interrupted.store(true);
}

/// Ctrl-C sets g_interrupted (a render then ends with the passes finished so far); a
/// second one kills nori the usual way.
void catchInterrupt() {
    struct sigaction action {};
    action.sa_handler = onInterrupt;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESETHAND;
    sigaction(SIGINT, &action, nullptr);
}

const char *kDescription =
    R"(Renders a scene file to <file>.exr (linear) and <file>.png (sRGB) next to it, or runs a
test file (root element <test>) and exits 0 when it passes, 1 when it fails.)";

const char *kFooter = R"(
The image is rendered in passes over the whole frame (1, 1, 2, 4, ... samples per
pixel, at most 64 per pass). On Ctrl-C the passes finished so far are written to
<file>_partial.exr/.png, a whole frame at fewer samples, and nori exits with status
130; a second Ctrl-C ends it at once.

Split renders: `nori scene.xml --part K/N` for K = 1..N (separate processes or machines,
e.g. the Slurm job array of scripts/slurm/render.sh), then `nori merge parts*.exr -o OUT`
writes OUT.exr and OUT.png: the image of the whole render, its AOV layers merged too.
The merge refuses parts of another scene (a hash of every file the scene reads, and of
the -D definitions), of another spp, resolution or filter, a part given twice, and
missing parts unless --allow-missing (which merges those given and names the others).)";

/// How often a render writes its checkpoint by default: a render shorter than this
/// writes none.
constexpr double kDefaultCheckpointMinutes = 10.0;

/// More threads than this is a mistake, not a machine (TBB fails far above it).
constexpr int kMaxThreads = 1024;

struct Options {
    std::string sceneFile;
    std::string output;
    Defines defines;
    std::string convention;            ///< --convention (--camera-convention): "epfl" or "eth"
    std::vector<std::string> builtins; ///< --builtin: our plugins to use instead of a user's
    int threads = 0;
    size_t samplesPerPixel = 0;
    std::optional<uint64_t> renderSeed; ///< --seed for a render: the sampler's seed
    double timeBudget = 0.0;
    /// --checkpoint: minutes between checkpoints (0: after every pass; none: never).
    std::optional<double> checkpointMinutes = kDefaultCheckpointMinutes;
    bool resume = false; ///< --resume: continue from the checkpoint
    std::vector<AOV> aovs;
    bool pfm = false;
    bool denoise = false;
    bool showProgress = true;
    std::optional<int> previewPort; ///< --preview: serve the live preview on this port
    bool previewWait = false;
    float exposure = 0.0f;
    bool version = false;
    bool listPlugins = false;
    std::string listWhat; ///< the KIND or NAME after --list-plugins
    std::string markdownFile;
    std::vector<std::string> pluginsToTest;
    bool testAllPlugins = false;
    int soakSeeds = 0;
    PluginTestOptions pluginTest;
    std::optional<PartSpec> part;
    bool merge = false;   ///< `nori merge`: merge `parts` into `output`
    bool convert = false; ///< `nori convert`: write `convertInput` as our XML into `output`
    std::string convertInput;
    std::string format; ///< --format: "nori", "mitsuba" or "" (by the file)
    std::vector<std::string> parts;
    bool allowMissing = false;
    std::vector<std::string> renderOnlyFlags; ///< given flags that merge does not take
};

/// What the command line gives as text, checked and converted by checkOptions (with the
/// same messages whatever the program that reads it).
struct OptionTexts {
    std::vector<std::string> defines;
    std::string threads, spp, time, aovs, exposure, part, seed, seeds, checkpoint;
    int previewPort = 0;
};

int parsePositive(const std::string &text, const std::string &flag) {
    int value = toInt(text, flag);
    if (value <= 0)
        throw NoriException("{} must be a positive integer, got '{}'", flag, text);
    return value;
}

float parseExposure(const std::string &text, const std::string &flag) {
    const float exposure = toFloat(text, flag);
    if (!std::isfinite(exposure) || std::abs(exposure) > 64.0f)
        throw NoriException("{} must lie in [-64, 64] stops, got {}", flag, exposure);
    return exposure;
}

/// `--preview [PORT]`: the port is optional, so the next word is the port only when it is
/// a number (`--preview scene.xml` previews on the default port). The port is attached
/// here, the default one too, and CLI11 reads `--preview=PORT`.
std::vector<std::string> attachPreviewPorts(int argc, char **argv) {
    std::vector<std::string> arguments(argv, argv + argc);
    for (size_t i = 1; i < arguments.size(); ++i) {
        if (arguments[i] != "--preview" && arguments[i] != "--preview-wait")
            continue;
        if (i + 1 < arguments.size() &&
            std::isdigit(static_cast<unsigned char>(arguments[i + 1][0]))) {
            arguments[i] += "=" + arguments[i + 1];
            arguments.erase(arguments.begin() + static_cast<std::ptrdiff_t>(i) + 1);
        } else {
            arguments[i] += "=" + std::to_string(kDefaultPreviewPort);
        }
    }
    return arguments;
}

/// The options of `nori` and of `nori merge`, bound to `options` and `texts`.
void defineCommandLine(CLI::App &app, Options &options, OptionTexts &texts) {
    app.footer(kFooter);
    app.add_option("file", options.sceneFile,
                   "the scene or test file (.xml; a Mitsuba scene too), or a pbrt-v4 scene "
                   "(.pbrt, .pbrt.gz)");
    app.add_option("--format", options.format,
                   "read the XML file as ours (nori) or as Mitsuba's (mitsuba); by default a "
                   "<scene version=...> is Mitsuba's (docs/mitsuba-scenes.md)")
        ->type_name("nori|mitsuba")
        ->check(CLI::IsMember({"nori", "mitsuba"}));
    app.add_option("-D", texts.defines,
                   "define $name for the XML file (wins over <default>); repeatable")
        ->type_name("name=value")
        ->allow_extra_args(false);
    app.add_option("-o,--output", options.output,
                   "write FILE.exr and FILE.png instead (an .exr/.png suffix is dropped)")
        ->type_name("FILE");
    app.add_option("-t,--threads", texts.threads,
                   "number of worker threads, 1 to 1024 (default: all cores)")
        ->type_name("N");
    app.add_option("--spp", texts.spp, "samples per pixel, overriding the scene's sampler")
        ->type_name("N");
    app.add_option("--time", texts.time,
                   "time budget, the integrator's preparation (a photon map) included: render "
                   "passes until it is spent (the last one shortened to fit) or until the "
                   "sample count, whichever is first")
        ->type_name("SECONDS");
    app.add_option("--checkpoint", texts.checkpoint,
                   "write the render's state to <file>.checkpoint every MINUTES (default 10, "
                   "so shorter renders write none; 0: after every pass; off: never), "
                   "atomically; removed when the render completes")
        ->type_name("MINUTES");
    app.add_flag("--resume", options.resume,
                 "continue the render from <file>.checkpoint (same scene and options; --time "
                 "counts the time already spent): the image is the one the uninterrupted "
                 "render writes");
    app.add_option("--aovs", texts.aovs,
                   "AOV layers to add to the EXR, e.g. albedo,normal (from albedo, normal, "
                   "depth, position, sampleCount, variance, emission)")
        ->type_name("LIST");
    app.add_flag("--denoise", options.denoise,
                 "also write <file>_denoised.exr/.png, denoised by the built-in feature-guided "
                 "denoiser; the noisy image is written as always");
    app.add_flag("--pfm", options.pfm,
                 "also write <file>.pfm, <file>_albedo.pfm and <file>_normal.pfm, the inputs "
                 "of Intel Open Image Denoise's example tool");
    app.add_option("--exposure", texts.exposure,
                   "brighten the PNG by 2^E (E in stops, may be negative); the EXR keeps the "
                   "rendered values")
        ->type_name("E");
    app.add_option("--part", texts.part,
                   "render part K of N of the image's samples into <file>_partKofN.exr, with "
                   "the weights and header `nori merge` needs")
        ->type_name("K/N");
    app.add_option("--convention,--camera-convention", options.convention,
                   "the course conventions of cameras and shapes that do not choose their "
                   "own: epfl (Nori 2's, the default: image x mirrored, sphere u in [0, 1]) "
                   "or eth (the ETH course's: not mirrored, sphere u in [-1/2, 1/2])")
        ->type_name("epfl|eth");
    app.add_option("--builtin", options.builtins,
                   "use our plugin NAME, not the file of yours that registers the same name "
                   "(plugins/course/; nori says which of ours yours replace when it starts)")
        ->type_name("NAME")
        ->delimiter(',')
        ->allow_extra_args(false);
    auto *noProgress = app.add_flag("--no-progress", "no progress bar");
    app.add_option("--preview", texts.previewPort,
                   "show the render in a web browser while it runs, at http://127.0.0.1:PORT/ "
                   "(default 8080, loopback only; from another machine: ssh -L "
                   "8080:127.0.0.1:8080 HOST): the image after every pass, exposure, the AOV "
                   "layers, spp, ETA and a Stop button; for a test file, its χ² pictures")
        ->type_name("[PORT]");
    app.add_option("--preview-wait", texts.previewPort,
                   "as --preview, and keep serving the final image after the render ends, until "
                   "the page's Close button or Ctrl-C")
        ->type_name("[PORT]");
    app.add_option("--list-plugins", options.listWhat,
                   "list the plugins (of one kind: bsdf, emitter, ...) with a line on each, or "
                   "print one plugin's parameters, defaults and examples")
        ->type_name("[KIND|NAME]")
        ->expected(0, 1);
    app.add_option("--test-plugin", options.pluginsToTest,
                   "test plugins: BSDFs, phase functions and emitters by chi-square tests "
                   "of the examples of their doc comments, an integrator against the built-in "
                   "of its quantity (path_mis, ao, whitted, ...) on test scenes; exits 1 if "
                   "any fails")
        ->type_name("NAME");
    app.add_flag("--test-plugins", options.testAllPlugins,
                 "the same for every registered BSDF, phase function and emitter "
                 "(integrators: name them to --test-plugin)");
    app.add_option("--seed", texts.seed,
                   "the sampler's seed of a render, overriding the scene's (renders with other "
                   "seeds have independent noise), and the seed of --test-plugin (default 1)")
        ->type_name("S");
    app.add_option("--seeds", texts.seeds,
                   "soak: run --test-plugin(s) with seeds 1..N and count the failures of each "
                   "plugin against the 1% a correct one fails by chance")
        ->type_name("N");
    app.add_option("--pictures", options.pluginTest.pictureFolder,
                   "where --test-plugin and test files write pictures of failing chi-square "
                   "tests (default: the current folder, or the test file's)")
        ->type_name("DIR");
    app.add_flag("--all-pictures", options.pluginTest.allPictures, "pictures of every test");
    app.add_option("--plugins-markdown", options.markdownFile,
                   "write the plugin reference (docs/plugins.md) to FILE")
        ->type_name("FILE");
    app.add_flag("--version", options.version, "print the version");
    noProgress->each([&options](const std::string &) { options.showProgress = false; });

    CLI::App *merge = app.add_subcommand(
        "merge", "merge the parts of a split render (nori scene.xml --part K/N) into OUT.exr "
                 "and OUT.png");
    merge->footer("");
    merge->add_option("parts", options.parts, "the parts' EXR files")->type_name("PART.exr");
    merge->add_option("-o,--output", options.output, "write OUT.exr and OUT.png")->type_name("OUT");
    merge->add_flag("--allow-missing", options.allowMissing,
                    "merge the parts given and name the missing ones");
    merge->add_flag("--denoise", options.denoise, "also denoise the merged image");
    merge->add_option("--exposure", texts.exposure, "brighten the PNG by 2^E")->type_name("E");
    // Options of rendering given to merge reach the main command, which refuses them.
    merge->fallthrough();
    merge->callback([&options] { options.merge = true; });
    app.add_flag("--allow-missing", options.allowMissing, "(nori merge's)")->group("");

    CLI::App *convert = app.add_subcommand(
        "convert", "write a pbrt-v4 scene (.pbrt, .pbrt.gz) or a Mitsuba scene (.xml) as our "
                   "XML: OUT.xml (a pbrt-v4 scene's large inline meshes as PLY files in "
                   "OUT_meshes/; docs/pbrt-scenes.md, docs/mitsuba-scenes.md)");
    convert->footer("");
    convert->add_option("scene", options.convertInput, "the pbrt-v4 or Mitsuba file")
        ->type_name("SCENE");
    convert->add_option("-o,--output", options.output, "the XML file to write")
        ->type_name("OUT.xml");
    convert->callback([&options] { options.convert = true; });
}

/// Checks and converts the options given as text; throws NoriException naming the
/// option.
void checkOptions(const CLI::App &app, Options &options, const OptionTexts &texts) {
    for (const char *flag : {"--spp", "--time", "--aovs", "--pfm", "--part", "--convention",
                             "--preview", "--preview-wait", "-D", "--checkpoint", "--resume"})
        if (app.count(flag) > 0)
            options.renderOnlyFlags.emplace_back(flag);
    options.listPlugins = app.count("--list-plugins") > 0;
    for (const std::string &definition : texts.defines) {
        const size_t equals = definition.find('=');
        if (equals == std::string::npos || equals == 0)
            throw NoriException("-D expects name=value, got '{}'", definition);
        options.defines[definition.substr(0, equals)] = definition.substr(equals + 1);
    }
    if (!texts.threads.empty()) {
        options.threads = parsePositive(texts.threads, "--threads");
        if (options.threads > kMaxThreads)
            throw NoriException("--threads must be at most {}, got {}", kMaxThreads,
                                options.threads);
    }
    if (!texts.spp.empty())
        options.samplesPerPixel = static_cast<size_t>(parsePositive(texts.spp, "--spp"));
    if (!texts.time.empty()) {
        options.timeBudget = toFloat(texts.time, "--time");
        if (!(options.timeBudget > 0.0) || !std::isfinite(options.timeBudget))
            throw NoriException("--time must be a positive number of seconds, got {}",
                                options.timeBudget);
    }
    if (texts.checkpoint == "off") {
        options.checkpointMinutes.reset();
    } else if (!texts.checkpoint.empty()) {
        const float minutes = toFloat(texts.checkpoint, "--checkpoint");
        if (!(minutes >= 0.0f) || !std::isfinite(minutes))
            throw NoriException("--checkpoint must be a number of minutes (0 or more) or 'off', "
                                "got '{}'",
                                texts.checkpoint);
        options.checkpointMinutes = minutes;
    }
    if (!texts.aovs.empty())
        options.aovs = parseAOVList(texts.aovs, "--aovs");
    if (!texts.exposure.empty())
        options.exposure = parseExposure(texts.exposure, "--exposure");
    if (!texts.part.empty())
        options.part = parsePartSpec(texts.part, "--part");
    if (!options.convention.empty() && options.convention != "epfl" && options.convention != "eth")
        throw NoriException("--convention must be 'epfl' or 'eth', got '{}'", options.convention);
    if (!texts.seed.empty()) {
        options.pluginTest.seed = static_cast<uint64_t>(parsePositive(texts.seed, "--seed"));
        options.renderSeed = options.pluginTest.seed;
    }
    if (!texts.seeds.empty())
        options.soakSeeds = parsePositive(texts.seeds, "--seeds");
    const bool previewGiven = app.count("--preview") + app.count("--preview-wait") > 0;
    options.previewWait = app.count("--preview-wait") > 0;
    if (previewGiven) {
        if (texts.previewPort < 1 || texts.previewPort > 65535)
            throw NoriException("{} PORT must lie in [1, 65535], got {}",
                                options.previewWait ? "--preview-wait" : "--preview",
                                texts.previewPort);
        options.previewPort = texts.previewPort;
    }
}

/// Runs the plugin tests with seeds 1..seeds and prints, per plugin, how many runs
/// failed: a χ² rejection happens by chance in a fraction `significanceLevel` of runs of
/// a correct plugin; any other failure (a value check, a sample outside the domain) is
/// a bug whatever its rate.
int soakPlugins(const std::vector<std::string> &names, int seeds, PluginTestOptions options) {
    options.pictureFolder.clear();
    std::vector<int> rejections(names.size(), 0), otherFailures(names.size(), 0);
    std::vector<std::string> firstProblem(names.size());
    const auto start = std::chrono::steady_clock::now();
    for (int seed = 1; seed <= seeds; ++seed) {
        options.seed = static_cast<uint64_t>(seed);
        const auto results = testSamplingPlugins(names, options);
        for (size_t i = 0; i < names.size(); ++i) {
            if (results[i].passed)
                continue;
            const std::string &report = results[i].report;
            const size_t fail = report.find("FAIL: ");
            const std::string problem = report.substr(fail, report.find('\n', fail) - fail);
            (problem.rfind("FAIL: χ²: chi^2", 0) == 0 ? rejections : otherFailures)[i]++;
            if (firstProblem[i].empty())
                firstProblem[i] = fmt::format("seed {}: {}", seed, problem);
        }
        fmt::print(stderr, "\rsoak: seed {} of {}", seed, seeds);
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    fmt::print(stderr, "\n");
    fmt::print("{:<20} {:>14} {:>14}  first problem\n", "plugin", "χ² rejections",
               "other failures");
    int bugs = 0;
    for (size_t i = 0; i < names.size(); ++i) {
        fmt::print("{:<20} {:>9} of {:<3} {:>14}  {}\n", names[i], rejections[i], seeds,
                   otherFailures[i], firstProblem[i]);
        bugs += otherFailures[i];
    }
    fmt::print("expected χ² rejections of a correct plugin: {:.2f} of {} runs (significance {:g} "
               "per run); other failures: {}; {:.1f} s\n",
               options.significanceLevel * seeds, seeds, options.significanceLevel, bugs, seconds);
    return bugs == 0 ? 0 : 1;
}

/// The output path without extension: -o's argument, or the scene file's path (with
/// _partKofN for a part).
std::string outputStem(const Options &options) {
    fs::path path(options.output.empty() ? options.sceneFile : options.output);
    const std::string extension = toLower(path.extension().string());
    if (options.output.empty() || extension == ".exr" || extension == ".png")
        path.replace_extension();
    if (options.output.empty() && options.part)
        path += fmt::format("_part{}of{}", options.part->index, options.part->count);
    return path.string();
}

/// Writes beauty, albedo and normal as PFM files for OIDN's example tool (`oidnDenoise
/// --hdr <stem>.pfm --alb <stem>_albedo.pfm --nrm <stem>_normal.pfm`).
void writeDenoiserInputs(const LayeredImage &layers, const std::string &stem) {
    layers.layer("").savePFM(stem + ".pfm");
    layers.layer("albedo").savePFM(stem + "_albedo.pfm");
    layers.layer("normal").savePFM(stem + "_normal.pfm");
}

/// Denoises a finished render into <stem>_denoised.exr/.png, beside the noisy image, and
/// returns the denoised image.
Bitmap writeDenoised(const LayeredImage &layers, const std::string &stem, int threads,
                     float exposure) {
    DenoiserSettings settings;
    settings.threads = threads;
    const auto start = std::chrono::steady_clock::now();
    Bitmap denoised = denoise(layers, settings);
    denoised.saveEXR(stem + "_denoised.exr");
    denoised.savePNG(stem + "_denoised.png", exposure);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    fmt::print(stderr, "Denoised in {}; wrote {}_denoised.exr and {}_denoised.png\n",
               formatDuration(seconds), stem, stem);
    return denoised;
}

/// Renders the scene into its output files; shows it on `preview` (may be null) too.
int renderToFiles(Scene &scene, const Options &options, const std::string &hash,
                  PreviewServer *preview) {
    const Vector2i size = scene.getCamera()->getOutputSize();
    RenderOptions renderOptions;
    renderOptions.threads = options.threads > 0 ? options.threads : defaultThreadCount();
    renderOptions.samplesPerPixel = options.samplesPerPixel;
    if (options.renderSeed)
        scene.getSampler()->setSeed(*options.renderSeed);
    std::unique_ptr<ProgressBar> progress;
    if (options.showProgress)
        renderOptions.progress = [&progress](size_t done, size_t total) {
            if (!progress)
                progress = std::make_unique<ProgressBar>("Rendering", total, true);
            progress->update(done);
        };
    renderOptions.cancel = &g_interrupted;
    renderOptions.timeBudget = options.timeBudget;
    renderOptions.aovs = options.aovs;
    std::vector<AOV> needed;
    if (options.pfm)
        needed = {AOV::Albedo, AOV::Normal};
    if (options.denoise)
        needed.insert(needed.end(), denoiserAOVs().begin(), denoiserAOVs().end());
    for (AOV aov : needed)
        if (std::find(renderOptions.aovs.begin(), renderOptions.aovs.end(), aov) ==
            renderOptions.aovs.end())
            renderOptions.aovs.push_back(aov);
    fmt::print(stderr, "Rendering {} ({}x{}, {} spp{}, {} threads)\n", options.sceneFile, size.x(),
               size.y(),
               options.samplesPerPixel > 0 ? options.samplesPerPixel
                                           : scene.getSampler()->getSampleCount(),
               options.timeBudget > 0.0 ? fmt::format(" or {}", formatDuration(options.timeBudget))
                                        : std::string(),
               renderOptions.threads);

    // Checkpoints beside the output, of this scene and these options only.
    const std::string checkpointPath = checkpointFile(outputStem(options));
    CheckpointIdentity identity;
    identity.version = NORI_VERSION;
    identity.sceneHash = hash;
    {
        std::vector<std::string> aovNames;
        for (AOV aov : renderOptions.aovs)
            aovNames.emplace_back(aovName(aov));
        identity.options = {
            {"--spp", options.samplesPerPixel > 0 ? std::to_string(options.samplesPerPixel) : ""},
            {"--seed", options.renderSeed ? std::to_string(*options.renderSeed) : ""},
            {"--aovs", fmt::format("{}", fmt::join(aovNames, ","))},
            {"--part",
             options.part ? fmt::format("{}/{}", options.part->index, options.part->count) : ""},
            {"--builtin", fmt::format("{}", fmt::join(options.builtins, ","))},
            {"--format", options.format}};
    }
    std::string resumeState;
    if (options.resume) {
        if (!fs::exists(checkpointPath))
            throw NoriException("--resume: there is no checkpoint '{}' (a render writes one "
                                "every --checkpoint minutes)",
                                checkpointPath);
        resumeState = decodeCheckpoint(readBinaryFile(checkpointPath, "checkpoint"), checkpointPath,
                                       identity);
        renderOptions.resumeState = &resumeState;
        renderOptions.resumeName = fmt::format("checkpoint '{}'", checkpointPath);
    }
    if (options.checkpointMinutes) {
        renderOptions.checkpointSeconds = *options.checkpointMinutes * 60.0;
        renderOptions.checkpoint = [&](const std::string &state) {
            writeBinaryFile(checkpointPath, encodeCheckpoint(identity, state), "checkpoint");
        };
    }

    if (options.part) {
        const size_t total = options.samplesPerPixel > 0 ? options.samplesPerPixel
                                                         : scene.getSampler()->getSampleCount();
        const SampleSlice slice = partSamples(*options.part, total);
        fmt::print(stderr,
                   "Part {} of {}: sample indices {} to {} of every pixel (scene hash {})\n",
                   options.part->index, options.part->count, slice.first,
                   slice.first + slice.count - 1, hash);
    }
    fmt::print(stderr, "Scene: {}\n", scene.statisticsSummary());
    if (preview) {
        preview->beginRender(options.samplesPerPixel > 0 ? options.samplesPerPixel
                                                         : scene.getSampler()->getSampleCount(),
                             options.timeBudget);
        renderOptions.passFinished = [preview](const Film &film, const PassReport &report) {
            preview->passFinished(film, report);
        };
    }
    const uint64_t raysBefore = scene.rayCount();
    RenderResult result = options.part ? renderPart(scene, renderOptions, *options.part, hash,
                                                    fs::path(options.sceneFile).filename().string())
                                       : renderScene(scene, renderOptions);
    const double rays = static_cast<double>(scene.rayCount() - raysBefore);
    if (progress)
        progress->finish();

    if (result.resumedSamplesPerPixel > 0)
        fmt::print(stderr, "Resumed from {} at {} spp\n", checkpointPath,
                   result.resumedSamplesPerPixel);
    const std::string stem = outputStem(options) + (result.cancelled ? "_partial" : "");
    result.layers.saveEXR(stem + ".exr");
    result.image.savePNG(stem + ".png", options.exposure);
    if (result.complete) {
        std::error_code ignored; // the image is written: its checkpoint has done its job
        fs::remove(checkpointPath, ignored);
    } else if (result.cancelled && fs::exists(checkpointPath)) {
        fmt::print(stderr, "Checkpoint: {} (nori --resume continues the render)\n", checkpointPath);
    }
    if (options.pfm)
        writeDenoiserInputs(result.layers, stem);
    if (result.invalidSamples > 0)
        fmt::print(stderr,
                   "Warning: {} of {} samples had NaN, infinite or negative radiance and were "
                   "not splatted\n",
                   result.invalidSamples, result.samplesTaken + result.invalidSamples);
    if (result.convergedPixels > 0)
        fmt::print(stderr,
                   "Adaptive sampling stopped {} of {} pixels early: {:.1f} samples per pixel on "
                   "average\n",
                   result.convergedPixels, size.prod(),
                   static_cast<double>(result.samplesTaken) / size.prod());
    if (preview)
        fmt::print(stderr, "Preview: {}\n",
                   preview->costSummary(result.seconds, renderOptions.threads));
    if (preview && (result.cancelled || !options.denoise))
        preview->finishRender(result.layers, result.cancelled, result.seconds,
                              result.samplesPerPixel);
    if (result.cancelled && result.passes == 0) {
        fmt::print(stderr,
                   "Interrupted before the first pass finished: wrote a black frame to {}.exr "
                   "and {}.png\n",
                   stem, stem);
        return kExitInterrupted;
    }
    if (result.cancelled) {
        fmt::print(stderr,
                   "Interrupted: wrote the {} finished passes ({} of {} spp, a whole frame) to "
                   "{}.exr and {}.png\n",
                   result.passes, result.samplesPerPixel, result.targetSamplesPerPixel, stem, stem);
        return kExitInterrupted;
    }
    if (!result.complete)
        fmt::print(stderr, "Time budget of {} spent: {} of {} spp in {} passes\n",
                   formatDuration(options.timeBudget), result.samplesPerPixel,
                   result.targetSamplesPerPixel, result.passes);
    fmt::print(stderr,
               "Done in {} ({} spp; {:.2f} M samples/s; {:.1f} M rays traced, {:.2f} M rays/s); "
               "wrote {}.exr and {}.png\n",
               formatDuration(result.seconds), result.samplesPerPixel,
               static_cast<double>(result.samplesTaken) / result.seconds * 1e-6, rays * 1e-6,
               rays / result.seconds * 1e-6, stem, stem);
    if (const std::string summary = scene.getIntegrator()->renderSummary(); !summary.empty())
        fmt::print(stderr, "{}\n", summary);
    if (options.denoise) {
        const Bitmap denoised =
            writeDenoised(result.layers, stem, renderOptions.threads, options.exposure);
        if (preview) {
            result.layers.addLayer("denoised", {"R", "G", "B"}, denoised);
            preview->finishRender(std::move(result.layers), false, result.seconds,
                                  result.samplesPerPixel);
        }
    }
    return 0;
}

/// `nori merge PART.exr... -o OUT`: the merged image, denoised too with --denoise.
int mergeCommand(const Options &options) {
    if (options.output.empty())
        throw NoriException("merge: no output given (-o OUT writes OUT.exr and OUT.png)");
    const std::string stem = outputStem(options);
    const MergeResult merged = mergeParts(options.parts, options.allowMissing);
    merged.image.saveEXR(stem + ".exr");
    merged.image.layer("").savePNG(stem + ".png", options.exposure);
    if (!merged.missing.empty())
        fmt::print(stderr,
                   "Warning: merged {} of {} spp; missing part{} {} of {} (--allow-missing)\n",
                   merged.samplesPerPixel, merged.totalSamplesPerPixel,
                   merged.missing.size() > 1 ? "s" : "", fmt::join(merged.missing, ", "),
                   merged.partCount);
    fmt::print(stderr, "Merged {} parts ({} spp); wrote {}.exr and {}.png\n", options.parts.size(),
               merged.samplesPerPixel, stem, stem);
    if (options.denoise)
        writeDenoised(merged.image, stem,
                      options.threads > 0 ? options.threads : defaultThreadCount(),
                      options.exposure);
    return 0;
}

/// A folder of its own under the system's temporary folder, removed with everything in it
/// when this goes out of scope.
class TemporaryFolder {
public:
    TemporaryFolder() {
        static std::atomic<int> counter{0};
        m_path = fs::temp_directory_path() / fmt::format("nori-{}-{}", getpid(), counter++);
    }
    ~TemporaryFolder() {
        std::error_code ignored;
        fs::remove_all(m_path, ignored);
    }
    TemporaryFolder(const TemporaryFolder &) = delete;
    TemporaryFolder &operator=(const TemporaryFolder &) = delete;
    std::string path() const { return m_path.string(); }

private:
    fs::path m_path;
};

void printWarnings(const std::vector<std::string> &warnings) {
    for (const std::string &warning : warnings)
        fmt::print(stderr, "Warning: {}\n", warning);
}

/// Whether `file` is to be read as a Mitsuba scene: as --format says, else when its
/// <scene> has a version attribute.
bool readsAsMitsuba(const std::string &file, const std::string &format) {
    return format == "mitsuba" || (format.empty() && mitsuba::isMitsubaFile(file));
}

/// The Mitsuba scene `file` as our XML, to be read from `xmlDirectory`.
mitsuba::Conversion convertMitsuba(const std::string &file, const Defines &defines,
                                   const std::string &xmlDirectory) {
    mitsuba::ConvertOptions convertOptions;
    convertOptions.defines = defines;
    convertOptions.xmlDirectory = xmlDirectory;
    mitsuba::Conversion conversion = mitsuba::convertFile(file, convertOptions);
    printWarnings(conversion.warnings);
    return conversion;
}

/// Loads our XML, a Mitsuba file or a pbrt-v4 file through its importer (their XML loaded
/// from memory; pbrt-v4's grids kept in a temporary folder until the load has read them).
/// `format` is --format's ("", "nori" or "mitsuba"). `outputName` receives a pbrt-v4
/// film's filename.
std::shared_ptr<NoriObject> loadSceneFile(const std::string &file, const std::string &format,
                                          const LoadOptions &loadOptions, std::string &outputName) {
    const std::string folder = fs::path(file).parent_path().string();
    if (format != "nori" && readsAsMitsuba(file, format)) {
        const mitsuba::Conversion conversion =
            convertMitsuba(file, loadOptions.defines, folder.empty() ? "." : folder);
        // -D names the Mitsuba file's $variables, not our XML's.
        LoadOptions xmlOptions = loadOptions;
        xmlOptions.defines.clear();
        if (loadOptions.unusedDefines)
            for (const auto &[name, value] : loadOptions.defines)
                if (std::find(conversion.variables.begin(), conversion.variables.end(), name) ==
                    conversion.variables.end())
                    loadOptions.unusedDefines->push_back(name);
        xmlOptions.unusedDefines = nullptr;
        return loadFromXMLString(conversion.xml, folder.empty() ? "." : folder, xmlOptions);
    }
    if (!pbrt::isPbrtFile(file))
        return loadFromXML(file, loadOptions);
    const TemporaryFolder sideFiles;
    pbrt::ConvertOptions convertOptions;
    convertOptions.xmlDirectory = folder.empty() ? "." : folder;
    convertOptions.sideFileDirectory = sideFiles.path();
    const pbrt::Conversion conversion = pbrt::convertFile(file, convertOptions);
    printWarnings(conversion.warnings);
    outputName = conversion.outputName;
    return loadFromXMLString(conversion.xml, convertOptions.xmlDirectory, loadOptions);
}

/// `nori convert SCENE.pbrt -o OUT.xml`: our XML, large inline meshes as PLY files beside
/// it; `nori convert SCENE.xml -o OUT.xml` for a Mitsuba scene.
int convertCommand(const Options &options) {
    if (options.convertInput.empty())
        throw NoriException("convert: no scene given (nori convert SCENE.pbrt|SCENE.xml -o "
                            "OUT.xml)");
    requireRegularFile(options.convertInput, "scene");
    const bool isMitsuba =
        options.format != "nori" && readsAsMitsuba(options.convertInput, options.format);
    if (!isMitsuba && !pbrt::isPbrtFile(options.convertInput))
        throw NoriException("convert: '{}' is neither a pbrt-v4 file (.pbrt or .pbrt.gz) nor "
                            "a Mitsuba scene (a <scene version=...>)",
                            options.convertInput);
    if (options.output.empty())
        throw NoriException("convert: no output given (-o OUT.xml)");
    fs::path output(options.output);
    if (toLower(output.extension().string()) != ".xml")
        output += ".xml";
    if (isMitsuba) {
        const std::string folder = output.parent_path().string();
        const mitsuba::Conversion conversion =
            convertMitsuba(options.convertInput, options.defines, folder.empty() ? "." : folder);
        if (!output.parent_path().empty())
            fs::create_directories(output.parent_path());
        writeBinaryFile(output.string(), conversion.xml, "the converted scene");
        fmt::print(stderr, "Wrote {}\n", output.string());
        return 0;
    }
    pbrt::ConvertOptions convertOptions;
    const std::string folder = output.parent_path().string();
    convertOptions.xmlDirectory = folder.empty() ? "." : folder;
    convertOptions.inlineVertexLimit = 256;
    convertOptions.sideFileDirectory =
        (output.parent_path() / (output.stem().string() + "_meshes")).string();
    const pbrt::Conversion conversion = pbrt::convertFile(options.convertInput, convertOptions);
    printWarnings(conversion.warnings);
    if (!output.parent_path().empty())
        fs::create_directories(output.parent_path());
    writeBinaryFile(output.string(), conversion.xml, "the converted scene");
    fmt::print(stderr, "Wrote {}{}\n", output.string(),
               conversion.sideFiles.empty()
                   ? std::string()
                   : fmt::format(" and {} file{} in {}", conversion.sideFiles.size(),
                                 conversion.sideFiles.size() > 1 ? "s" : "",
                                 convertOptions.sideFileDirectory));
    return 0;
}

/// Loads the scene or test file and renders or runs it; shows it on `preview` (may be null).
int loadAndRun(const Options &options, PreviewServer *preview) {
    LoadOptions loadOptions(options.defines);
    loadOptions.convention = options.convention;
    std::vector<std::string> unusedDefines;
    loadOptions.unusedDefines = &unusedDefines;
    // For the scene hash of a split render's parts and of checkpoints.
    std::optional<ReadFileRecorder> readFiles;
    if (options.part || options.checkpointMinutes || options.resume)
        readFiles.emplace();
    std::string outputName;
    const auto loadStart = std::chrono::steady_clock::now();
    std::shared_ptr<NoriObject> root =
        loadSceneFile(options.sceneFile, options.format, loadOptions, outputName);
    const double loadSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - loadStart).count();
    const std::string hash =
        readFiles ? sceneHash(readFiles->digests(), options.defines, options.convention)
                  : std::string();
    readFiles.reset();
    for (const std::string &name : unusedDefines)
        fmt::print(stderr, "Warning: -D {}={} is not used: {} has no ${}\n", name,
                   options.defines.at(name), options.sceneFile, name);
    if (auto test = std::dynamic_pointer_cast<Test>(root)) {
        fmt::print("{}", testSampleScaleNotice());
        TestOptions testOptions;
        testOptions.allPictures = options.pluginTest.allPictures;
        testOptions.pictureFolder = options.pluginTest.pictureFolder;
        if (testOptions.pictureFolder.empty()) {
            // Next to the test file, as renders are.
            const std::string folder = fs::path(options.sceneFile).parent_path().string();
            testOptions.pictureFolder = folder.empty() ? "." : folder;
        }
        if (preview) {
            // The pictures are what the preview is for: one of every case, as it is drawn.
            testOptions.allPictures = true;
            testOptions.pictureWritten = [preview](const std::string &file,
                                                   const std::string &title) {
                preview->addPicture(file, title);
            };
            preview->beginTest();
        }
        const bool passed = test->run(testOptions);
        if (preview)
            preview->finishTest(passed);
        return passed ? 0 : 1;
    }
    if (auto scene = std::dynamic_pointer_cast<Scene>(root)) {
        // Time to first pixel: parsing, reading meshes and textures, building the BVH.
        fmt::print(stderr, "Loaded {} in {}\n", options.sceneFile, formatDuration(loadSeconds));
        catchInterrupt();
        if (options.output.empty() && !outputName.empty()) {
            // A pbrt-v4 film's filename names the output, next to the scene file as ours are.
            Options named = options;
            named.output = (fs::path(options.sceneFile).parent_path() /
                            fs::path(outputName).filename().replace_extension())
                               .string();
            return renderToFiles(*scene, named, hash, preview);
        }
        return renderToFiles(*scene, options, hash, preview);
    }
    throw NoriException("{}: the root element must be a <scene> or a <test>, not a {}",
                        options.sceneFile, NoriObject::classTypeName(root->getClassType()));
}

int run(Options &options) {
    NoriObjectFactory::checkRegistry();
    for (const std::string &name : options.builtins)
        NoriObjectFactory::useBuiltin(name);
    for (const NoriObjectFactory::Replacement &replacement : NoriObjectFactory::replacements())
        fmt::print(stderr, "nori: your {} '{}' ({}) replaces ours ({}); --builtin {} uses ours\n",
                   NoriObject::classTypeName(replacement.type), replacement.name,
                   shortSourcePath(replacement.yourFile), shortSourcePath(replacement.ourFile),
                   replacement.name);
    if (options.version) {
        fmt::print("nori {}\n{}\n", NORI_VERSION, buildDescription());
        return 0;
    }
    if (options.listPlugins) {
        fmt::print("{}", options.listWhat.empty() ? pluginList()
                         : NoriObjectFactory::isRegistered(options.listWhat)
                             ? pluginReference(options.listWhat)
                             : pluginList(options.listWhat));
        return 0;
    }
    if (options.testAllPlugins || !options.pluginsToTest.empty()) {
        if (options.previewPort)
            throw NoriException("--preview shows a render or a test file, not --test-plugin(s): "
                                "give it the test file (e.g. scenes/tests/chi2test-bsdfs.xml)");
        if (options.pluginTest.pictureFolder.empty())
            options.pluginTest.pictureFolder = ".";
        fmt::print("{}", testSampleScaleNotice());
        const std::vector<std::string> names =
            options.testAllPlugins ? samplingPlugins() : options.pluginsToTest;
        for (const std::string &name : names)
            if (!NoriObjectFactory::isRegistered(name))
                NoriObjectFactory::createInstance(name, NoriObject::EBSDF, {}); // did you mean
        if (options.soakSeeds > 0)
            return soakPlugins(names, options.soakSeeds, options.pluginTest);
        // One verdict on several plugins is one test of them all: each plugin is tested at
        // the Šidák-corrected level, so that a run of correct plugins fails by chance with
        // the stated probability overall, not once per plugin (26 plugins at 1% each would
        // fail one run in four).
        PluginTestOptions testOptions = options.pluginTest;
        testOptions.significanceLevel =
            sidakCorrection(options.pluginTest.significanceLevel, static_cast<int>(names.size()));
        // Integrators are tested one after the other (each render uses every core); the
        // sampling plugins in parallel.
        std::vector<std::string> samplingNames;
        for (const std::string &name : names)
            if (!isIntegratorPlugin(name))
                samplingNames.push_back(name);
        const auto samplingResults = testSamplingPlugins(samplingNames, testOptions);
        std::vector<std::string> failed, untested;
        size_t samplingIndex = 0;
        for (const std::string &name : names) {
            const PluginTestResult result = isIntegratorPlugin(name)
                                                ? testIntegratorPlugin(name, testOptions)
                                                : samplingResults[samplingIndex++];
            fmt::print("{}\n", result.report);
            if (!result.passed)
                failed.push_back(name);
            else if (!result.tested)
                untested.push_back(name);
        }
        if (names.size() > 1)
            fmt::print("significance {:g} over all {} plugins ({:.3g} each)\n",
                       options.pluginTest.significanceLevel, names.size(),
                       testOptions.significanceLevel);
        // A plugin that was not tested has not passed: the summary counts it apart.
        const size_t tested = names.size() - untested.size();
        if (!untested.empty())
            fmt::print("not tested: {}\n", fmt::join(untested, ", "));
        fmt::print("{} of {} tested plugins passed{}\n", tested - failed.size(), tested,
                   failed.empty() ? "" : fmt::format("; failed: {}", fmt::join(failed, ", ")));
        if (tested == 0) {
            fmt::print("nothing was tested: no verdict\n");
            return 1;
        }
        return failed.empty() ? 0 : 1;
    }
    if (!options.markdownFile.empty()) {
        writeFileIfChanged(options.markdownFile, pluginsMarkdown());
        return 0;
    }
    if (options.merge) {
        if (!options.renderOnlyFlags.empty())
            throw NoriException("merge: {} applies to rendering, not to merging parts",
                                options.renderOnlyFlags.front());
        return mergeCommand(options);
    }
    if (options.convert) {
        if (!options.renderOnlyFlags.empty())
            throw NoriException("convert: {} applies to rendering, not to converting",
                                options.renderOnlyFlags.front());
        return convertCommand(options);
    }
    if (options.allowMissing)
        throw NoriException("--allow-missing applies to `nori merge`, not to rendering");
    if (options.sceneFile.empty())
        throw NoriException("no scene or test file given (see nori --help)");
    if (options.part && options.denoise)
        throw NoriException("--denoise denoises a whole render: give it to `nori merge` instead "
                            "of to a part");

    // The preview starts before the scene loads, so a busy port is reported at once.
    std::unique_ptr<PreviewServer> preview;
    if (options.previewPort) {
        preview = std::make_unique<PreviewServer>(
            *options.previewPort, fs::path(options.sceneFile).filename().string(), &g_interrupted);
        fmt::print(stderr, "Preview: {} (from another machine: ssh -L {}:127.0.0.1:{} HOST)\n",
                   preview->url(), preview->port(), preview->port());
    }
    int status = 0;
    try {
        status = loadAndRun(options, preview.get());
    } catch (const std::bad_alloc &) {
        throw; // runProgram words it
    } catch (const std::exception &error) {
        if (!preview)
            throw;
        preview->fail(error.what());
        fmt::print(stderr, "Error: {}\n", error.what());
        status = 1;
    }
    if (preview && options.previewWait) {
        // Keep serving the final image: Ctrl-C or the page's Close button ends nori.
        g_interrupted.store(false);
        catchInterrupt();
        fmt::print(stderr,
                   "Preview: still serving {}; Ctrl-C or the page's Close button ends "
                   "nori\n",
                   preview->url());
        preview->waitForStop();
    }
    return status;
}

} // namespace

int main(int argc, char **argv) {
    Options options;
    OptionTexts texts;
    std::vector<std::string> arguments = attachPreviewPorts(argc, argv);
    std::vector<char *> pointers;
    pointers.reserve(arguments.size());
    for (std::string &argument : arguments)
        pointers.push_back(argument.data());
    return runCommandLine(
        static_cast<int>(pointers.size()), pointers.data(), "nori", kDescription,
        [&](CLI::App &app) { defineCommandLine(app, options, texts); },
        [&](const CLI::App &app) {
            checkOptions(app, options, texts);
            return run(options);
        });
}
