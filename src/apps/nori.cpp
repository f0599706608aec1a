// The `nori` program: renders a scene file to EXR + PNG, or runs a test file.
#include <nori/aov.h>
#include <nori/denoiser.h>
#include <nori/filesystem.h>
#include <nori/parser.h>
#include <nori/plugindoc.h>
#include <nori/plugintest.h>
#include <nori/preview.h>
#include <nori/program.h>
#include <nori/progress.h>
#include <nori/render.h>
#include <nori/renderpart.h>
#include <nori/scene.h>
#include <nori/strutil.h>
#include <nori/test.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <optional>
#include <set>
#include <signal.h>

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

const char *kUsage = R"(Usage: nori [options] <file.xml>
       nori merge PART.exr... -o OUT [--allow-missing] [--denoise] [--exposure E]

Renders a scene file to <file>.exr (linear) and <file>.png (sRGB) next to it, or runs a
test file (root element <test>) and exits 0 when it passes, 1 when it fails.

Options:
  -D name=value      define $name for the XML file (wins over <default>); repeatable
  -o, --output FILE  write FILE.exr and FILE.png instead (an .exr/.png suffix is dropped)
  -t, --threads N    number of worker threads, 1 to 1024 (default: all cores)
  --spp N            samples per pixel, overriding the scene's sampler
  --time SECONDS     time budget: render passes until it is spent (the last one
                     shortened to fit) or until the sample count, whichever is first
  --aovs LIST        AOV layers to add to the EXR, e.g. albedo,normal (from albedo,
                     normal, depth, position, sampleCount, variance; a scene can ask
                     for them with <string name="aovs" .../> on its integrator)
  --denoise          also write <file>_denoised.exr/.png, denoised by the built-in
                     feature-guided denoiser (it records the albedo, normal, depth and
                     variance layers it needs); the noisy image is written as always
  --pfm              also write <file>.pfm, <file>_albedo.pfm and <file>_normal.pfm,
                     the inputs of Intel Open Image Denoise's example tool
  --exposure E       brighten the PNG by 2^E (E in stops, may be negative); the EXR
                     keeps the rendered values
  --part K/N         render part K of N of the image's samples (the K-th of N slices of
                     every pixel's sample indices) into <file>_partKofN.exr, with the
                     weights and header `nori merge` needs (see "Split renders" below)
  --camera-convention epfl|eth
                     which way image x runs for cameras that do not say: epfl (x
                     mirrored, Nori 2's default) or eth (the ETH course's Nori)
  --no-progress      no progress bar
  --preview [PORT]   show the render in a web browser while it runs: serves a page at
                     http://127.0.0.1:PORT/ (default 8080, loopback only; from another
                     machine: ssh -L 8080:127.0.0.1:8080 HOST) with the image after every
                     pass, exposure, sRGB/linear, the AOV layers, spp, elapsed time, ETA and
                     a Stop button that ends the render as Ctrl-C does (status 130); for a
                     test file, the χ² picture of every case as it is drawn
  --preview-wait     as --preview, and keep serving the final image after the render
                     ends, until the page's Close button or Ctrl-C
  --list-plugins [KIND|NAME]
                     list the plugins (of one kind: bsdf, emitter, ...) with a line on
                     each, or print one plugin's parameters, defaults and examples
  --test-plugin NAME...
                     test sampling plugins (BSDFs, phase functions, emitters) built from
                     the examples of their doc comments: chi-square, weights, reciprocity,
                     energy, discrete laws; exits 1 if any fails
  --test-plugins     the same for every registered BSDF, phase function and emitter
  --seed S           the seed of --test-plugin (default 1)
  --seeds N          soak: run --test-plugin(s) with seeds 1..N and count the failures
                     of each plugin against the 1% a correct one fails by chance
  --pictures DIR     where --test-plugin writes pictures of failing chi-square tests
                     (default: the current folder); --all-pictures: of every test
  --plugins-markdown FILE
                     write the plugin reference (docs/plugins.md) to FILE
  --version          print the version
  -h, --help         this text

The image is rendered in passes over the whole frame (1, 1, 2, 4, ... samples per
pixel, at most 64 per pass). On Ctrl-C the passes finished so far are written to
<file>_partial.exr/.png, a whole frame at fewer samples, and nori exits with status
130; a second Ctrl-C ends it at once.

Split renders: `nori scene.xml --part K/N` for K = 1..N (separate processes or machines,
e.g. the Slurm job array of scripts/slurm/render.sh), then `nori merge parts*.exr -o OUT`
writes OUT.exr and OUT.png: the image of the whole render, its AOV layers merged too.
The merge refuses parts of another scene (a hash of every file the scene reads, and of
the -D definitions), of another spp, resolution or filter, a part given twice, and
missing parts unless --allow-missing (which merges those given and names the others).
)";

/// More threads than this is a mistake, not a machine (TBB fails far above it).
constexpr int kMaxThreads = 1024;

struct Options {
    std::string sceneFile;
    std::string output;
    Defines defines;
    std::string cameraConvention;
    int threads = 0;
    size_t samplesPerPixel = 0;
    double timeBudget = 0.0;
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
    bool help = false;
    std::optional<PartSpec> part;
    bool merge = false; ///< `nori merge`: merge `parts` into `output`
    std::vector<std::string> parts;
    bool allowMissing = false;
    std::vector<std::string> renderOnlyFlags; ///< given flags that merge does not take
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

Options parseCommandLine(int argc, char **argv) {
    Options options;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto value = [&](const std::string &flag) -> std::string {
            if (i + 1 >= argc)
                throw NoriException("option {} needs a value", flag);
            return argv[++i];
        };
        static const std::set<std::string> kRenderOnly = {
            "--spp",     "--time",        "--aovs", "--pfm", "--part", "--camera-convention",
            "--preview", "--preview-wait"};
        if (kRenderOnly.count(arg) || arg.rfind("-D", 0) == 0)
            options.renderOnlyFlags.push_back(arg);
        if (arg == "-h" || arg == "--help") {
            options.help = true;
        } else if (arg == "--list-plugins") {
            options.listPlugins = true;
            if (i + 1 < argc && argv[i + 1][0] != '-' && !endsWith(toLower(argv[i + 1]), ".xml"))
                options.listWhat = argv[++i];
        } else if (arg == "--test-plugin") {
            options.pluginsToTest.push_back(value(arg));
            while (i + 1 < argc && argv[i + 1][0] != '-')
                options.pluginsToTest.push_back(argv[++i]);
        } else if (arg == "--test-plugins") {
            options.testAllPlugins = true;
        } else if (arg == "--seed") {
            options.pluginTest.seed = static_cast<uint64_t>(parsePositive(value(arg), arg));
        } else if (arg == "--seeds") {
            options.soakSeeds = parsePositive(value(arg), arg);
        } else if (arg == "--pictures") {
            options.pluginTest.pictureFolder = value(arg);
        } else if (arg == "--all-pictures") {
            options.pluginTest.allPictures = true;
        } else if (arg == "--plugins-markdown") {
            options.markdownFile = value(arg);
        } else if (arg == "--version") {
            options.version = true;
        } else if (arg == "--exposure") {
            options.exposure = parseExposure(value(arg), arg);
        } else if (arg == "--no-progress") {
            options.showProgress = false;
        } else if (arg == "--preview" || arg == "--preview-wait") {
            options.previewWait = options.previewWait || arg == "--preview-wait";
            if (!options.previewPort)
                options.previewPort = kDefaultPreviewPort;
            // An optional port: the next argument when it is a number.
            if (i + 1 < argc && std::isdigit(static_cast<unsigned char>(argv[i + 1][0]))) {
                options.previewPort = toInt(argv[++i], arg);
                if (*options.previewPort < 1 || *options.previewPort > 65535)
                    throw NoriException("{} PORT must lie in [1, 65535], got {}", arg,
                                        *options.previewPort);
            }
        } else if (arg == "-o" || arg == "--output") {
            options.output = value(arg);
        } else if (arg == "-t" || arg == "--threads") {
            options.threads = parsePositive(value(arg), arg);
            if (options.threads > kMaxThreads)
                throw NoriException("{} must be at most {}, got {}", arg, kMaxThreads,
                                    options.threads);
        } else if (arg == "--camera-convention") {
            options.cameraConvention = value(arg);
            if (options.cameraConvention != "epfl" && options.cameraConvention != "eth")
                throw NoriException("--camera-convention must be 'epfl' or 'eth', got '{}'",
                                    options.cameraConvention);
        } else if (arg == "--time") {
            options.timeBudget = toFloat(value(arg), arg);
            if (!(options.timeBudget > 0.0) || !std::isfinite(options.timeBudget))
                throw NoriException("--time must be a positive number of seconds, got {}",
                                    options.timeBudget);
        } else if (arg == "--aovs") {
            options.aovs = parseAOVList(value(arg), arg);
        } else if (arg == "--pfm") {
            options.pfm = true;
        } else if (arg == "--denoise") {
            options.denoise = true;
        } else if (arg == "--part") {
            options.part = parsePartSpec(value(arg), arg);
        } else if (arg == "--spp") {
            options.samplesPerPixel = static_cast<size_t>(parsePositive(value(arg), arg));
        } else if (arg.rfind("-D", 0) == 0) {
            const std::string definition = arg.size() > 2 ? arg.substr(2) : value(arg);
            const size_t equals = definition.find('=');
            if (equals == std::string::npos || equals == 0)
                throw NoriException("-D expects name=value, got '{}'", definition);
            options.defines[definition.substr(0, equals)] = definition.substr(equals + 1);
        } else if (arg == "--allow-missing") {
            options.allowMissing = true;
        } else if (!arg.empty() && arg[0] == '-') {
            throw NoriException("unknown option '{}' (see nori --help)", arg);
        } else if (arg == "merge" && !options.merge && options.sceneFile.empty()) {
            options.merge = true;
        } else if (options.merge) {
            options.parts.push_back(arg);
        } else if (options.sceneFile.empty()) {
            options.sceneFile = arg;
        } else {
            throw NoriException("more than one input file given ('{}' and '{}')", options.sceneFile,
                                arg);
        }
    }
    return options;
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
    const Bitmap denoised = denoise(layers, settings);
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
    renderOptions.showProgress = options.showProgress;
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

    const std::string stem = outputStem(options) + (result.cancelled ? "_partial" : "");
    result.layers.saveEXR(stem + ".exr");
    result.image.savePNG(stem + ".png", options.exposure);
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

/// Loads the scene or test file and renders or runs it; shows it on `preview` (may be null).
int loadAndRun(const Options &options, PreviewServer *preview) {
    LoadOptions loadOptions(options.defines);
    loadOptions.cameraConvention = options.cameraConvention;
    std::vector<std::string> unusedDefines;
    loadOptions.unusedDefines = &unusedDefines;
    std::optional<ReadFileRecorder> readFiles; // for the scene hash of a split render
    if (options.part)
        readFiles.emplace();
    std::shared_ptr<NoriObject> root = loadFromXML(options.sceneFile, loadOptions);
    const std::string hash =
        readFiles ? sceneHash(readFiles->digests(), options.defines, options.cameraConvention)
                  : std::string();
    readFiles.reset();
    for (const std::string &name : unusedDefines)
        fmt::print(stderr, "Warning: -D {}={} is not used: {} has no ${}\n", name,
                   options.defines.at(name), options.sceneFile, name);
    if (auto test = std::dynamic_pointer_cast<Test>(root)) {
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
        catchInterrupt();
        return renderToFiles(*scene, options, hash, preview);
    }
    throw NoriException("{}: the root element must be a <scene> or a <test>, not a {}",
                        options.sceneFile, NoriObject::classTypeName(root->getClassType()));
}

int run(int argc, char **argv) {
    NoriObjectFactory::checkRegistry();
    Options options = parseCommandLine(argc, argv);
    if (options.help) {
        fmt::print("{}", kUsage);
        return 0;
    }
    if (options.version) {
        fmt::print("nori {}\n", NORI_VERSION);
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
        const std::vector<std::string> names =
            options.testAllPlugins ? samplingPlugins() : options.pluginsToTest;
        for (const std::string &name : names)
            if (!NoriObjectFactory::isRegistered(name))
                NoriObjectFactory::createInstance(name, NoriObject::EBSDF, {}); // did you mean
        if (options.soakSeeds > 0)
            return soakPlugins(names, options.soakSeeds, options.pluginTest);
        std::vector<std::string> failed;
        const auto results = testSamplingPlugins(names, options.pluginTest);
        for (size_t i = 0; i < names.size(); ++i) {
            fmt::print("{}\n", results[i].report);
            if (!results[i].passed)
                failed.push_back(names[i]);
        }
        fmt::print("{} of {} plugins passed{}\n", names.size() - failed.size(), names.size(),
                   failed.empty() ? "" : fmt::format("; failed: {}", fmt::join(failed, ", ")));
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
    if (options.allowMissing)
        throw NoriException("--allow-missing applies to `nori merge`, not to rendering");
    if (options.sceneFile.empty()) {
        fmt::print(stderr, "{}", kUsage);
        return 1;
    }
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
    return runProgram([&] { return run(argc, argv); });
}
