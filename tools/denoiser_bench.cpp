// nori-bench-denoiser: the figures of the denoiser.
//   1. relMSE against converged references of the noisy and the denoised image at 4,
//      16 and 64 spp on the Cornell box, Veach's MIS scene and the textured scene, and
//      at its own 12 spp on the default scene (tests/denoiser_scenes.h), seed 1; with
//      an oracle's bound, and apart for the emitters' own pixels.
//   2. The time to denoise a 512×512 render of the Cornell box, median of 5.
//
//   nori-bench-denoiser [--threads N] [--write DIR]   (DIR: the images, as PFM and PNG)
//   nori-bench-denoiser --make-references   (renders tests/data/denoiser/*.exr)
//   nori-bench-denoiser --crops FILE.png    (the README's noisy/denoised/reference crops)
#include "app/cli.h"
#include "denoise/denoiser.h"
#include <nori/render.h>
#include <nori/scene.h>
#include <nori/strutil.h>

#include <denoiser_scenes.h>

#include <algorithm>
#include <chrono>
#include <iostream>

using namespace nori;
using namespace nori::denoiserscenes;

namespace {

const std::string kSourceDir = NORI_SOURCE_DIR;
using Mask = PixelMask;

RenderResult render(const DenoiserScene &entry, int spp, int seed, int threads,
                    const Defines &overrides = {}) {
    auto scene = load(entry, kSourceDir, spp, seed, overrides);
    RenderOptions options;
    options.threads = threads;
    options.aovs = denoiserAOVs();
    options.aovs.push_back(AOV::Emission);
    return renderScene(*scene, options);
}

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// What an oracle that knows the reference reaches with the denoiser's filters: each
/// pixel takes, of the candidates of bandwidths 0.25 to 4 (first-order fit, weighted
/// mean) and the noisy image, the one of least relative squared error against the
/// reference over the pixel's 3×3 neighbours. No denoiser can choose better among them.
Bitmap oracle(const LayeredImage &noisy, const Bitmap &reference, int threads) {
    DenoiserSettings settings;
    settings.threads = threads;
    settings.bandwidths = {0.25f, 0.5f, 1.0f, 2.0f, 4.0f};
    const std::vector<Bitmap> candidates = denoiserCandidates(noisy, settings);
    const int width = reference.width(), height = reference.height();
    std::vector<Eigen::ArrayXXd> errors;
    for (const Bitmap &candidate : candidates) {
        Eigen::ArrayXXd error(height, width);
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const Eigen::Array3d r = reference(y, x).cast<double>();
                error(y, x) =
                    ((candidate(y, x).cast<double>() - r).square() / (r.square() + 0.01)).sum();
            }
        errors.push_back(error);
    }
    Bitmap result(Vector2i(width, height));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const int y0 = std::max(0, y - 1), x0 = std::max(0, x - 1);
            const int rows = std::min(height - 1, y + 1) - y0 + 1;
            const int cols = std::min(width - 1, x + 1) - x0 + 1;
            size_t best = 0;
            for (size_t c = 1; c < candidates.size(); ++c)
                if (errors[c].block(y0, x0, rows, cols).sum() <
                    errors[best].block(y0, x0, rows, cols).sum())
                    best = c;
            result(y, x) = candidates[best](y, x);
        }
    return result;
}

void writeImages(const std::string &stem, const Bitmap &noisy, const Bitmap &denoised,
                 const Bitmap &reference) {
    for (const auto &[suffix, image] :
         {std::pair{"", &noisy}, {"_denoised", &denoised}, {"_reference", &reference}}) {
        image->savePFM(stem + suffix + ".pfm");
        image->savePNG(stem + suffix + ".png");
    }
}

/// One line of figures: relMSE noisy, denoised, their ratio and the oracle's ratio, over
/// the pixels of `mask` (all when null).
void printFigures(const std::string &label, const Bitmap &noisy, const Bitmap &denoised,
                  const Bitmap &best, const Bitmap &reference, const Mask *mask) {
    const double before = relativeMeanSquaredError(noisy, reference, mask);
    const double after = relativeMeanSquaredError(denoised, reference, mask);
    const double oracleError = relativeMeanSquaredError(best, reference, mask);
    std::cout << fmt::format(
        "{:<36} noisy {:.3e}  denoised {:.3e}  ratio {:5.1f}  oracle {:5.1f}\n", label, before,
        after, before / after, before / oracleError);
}

/// The figures of one scene at `spp` (0: the scene's own).
void measure(const DenoiserScene &entry, int spp, int threads, const std::string &writeFolder) {
    const Bitmap reference = Bitmap::load(referencePath(entry, kSourceDir));
    const RenderResult noisy = render(entry, spp, 1, threads);
    DenoiserSettings settings;
    settings.threads = threads;
    const auto start = std::chrono::steady_clock::now();
    const Bitmap denoised = denoise(noisy.layers, settings);
    const double seconds = secondsSince(start);
    const Bitmap best = oracle(noisy.layers, reference, threads);
    const int samples = static_cast<int>(noisy.samplesPerPixel);
    if (!writeFolder.empty())
        writeImages(fmt::format("{}/{}_{}", writeFolder, entry.name, samples), noisy.image,
                    denoised, reference);
    printFigures(fmt::format("{} {} spp ({:.2f} s)", entry.name, samples, seconds), noisy.image,
                 denoised, best, reference, nullptr);
    // The emitters' own pixels (and a 2-pixel rim) apart: their coverage noise is what
    // no feature explains.
    const Mask emitters = emitterPixels(noisy.layers.layer(aovName(AOV::Emission)), 2);
    const Mask outside = !emitters;
    std::cout << fmt::format("  fireflies smeared (outside the emitters, denoised above the "
                             "noisy image's 99.9th percentile where the reference is not): {}\n",
                             smearedFireflies(noisy.image, denoised, reference, outside));
    if (emitters.any()) {
        printFigures("  outside the emitters and a 2-px rim", noisy.image, denoised, best,
                     reference, &outside);
        printFigures(fmt::format("  the emitters' {} pixels", emitters.count()), noisy.image,
                     denoised, best, reference, &emitters);
    }
}

/// The region of a scene's image that the README's crops show.
struct Crop {
    const DenoiserScene *scene;
    int spp; ///< 0: the scene's own
    int x, y, width, height;
};

/// Writes one PNG of noisy / denoised / reference crops side by side, a row per scene,
/// each pixel shown as 2×2, on white: the README's denoising section.
void writeCrops(const std::string &file, int threads) {
    const std::vector<Crop> crops{{&scenes()[0], 16, 16, 56, 96, 64},
                                  {&scenes()[2], 16, 4, 24, 96, 64},
                                  {&scenes()[1], 16, 24, 40, 96, 56},
                                  {&defaultScene(), 0, 16, 56, 96, 64}};
    constexpr int kScale = 2, kGap = 6;
    int canvasWidth = kGap, canvasHeight = kGap;
    for (const Crop &crop : crops) {
        canvasWidth = std::max(canvasWidth, kGap + 3 * (crop.width * kScale + kGap));
        canvasHeight += crop.height * kScale + kGap;
    }
    Bitmap canvas(Vector2i(canvasWidth, canvasHeight));
    canvas.setConstant(Color3f(1.0f));
    int top = kGap;
    for (const Crop &crop : crops) {
        const RenderResult noisy = render(*crop.scene, crop.spp, 1, threads);
        DenoiserSettings settings;
        settings.threads = threads;
        const Bitmap denoised = denoise(noisy.layers, settings);
        const Bitmap reference = Bitmap::load(referencePath(*crop.scene, kSourceDir));
        int left = kGap;
        for (const Bitmap *image : {&noisy.image, &denoised, &reference}) {
            if (crop.x + crop.width > image->width() || crop.y + crop.height > image->height())
                throw NoriException("crop of {} outside its {}x{} image", crop.scene->name,
                                    image->width(), image->height());
            for (int y = 0; y < crop.height * kScale; ++y)
                for (int x = 0; x < crop.width * kScale; ++x)
                    canvas(top + y, left + x) = (*image)(crop.y + y / kScale, crop.x + x / kScale);
            left += crop.width * kScale + kGap;
        }
        top += crop.height * kScale + kGap;
    }
    canvas.savePNG(file);
    std::vector<std::string> names;
    names.reserve(crops.size());
    for (const Crop &crop : crops)
        names.push_back(crop.scene->name);
    std::cout << fmt::format("wrote {} (rows: {}; columns: noisy, denoised, reference)\n", file,
                             fmt::join(names, ", "));
}

int run(int threads, bool makeReferences, const std::string &writeFolder,
        const std::string &cropsFile) {
    if (!cropsFile.empty()) {
        writeCrops(cropsFile, threads);
        return 0;
    }
    if (makeReferences) {
        for (const DenoiserScene &entry : scenes()) {
            const RenderResult reference = render(entry, kReferenceSpp, 0, threads);
            reference.image.saveEXR(referencePath(entry, kSourceDir));
            std::cout << fmt::format("{}: {} spp in {:.1f} s -> {}\n", entry.name, kReferenceSpp,
                                     reference.seconds, referencePath(entry, kSourceDir));
        }
        return 0;
    }

    std::cout << "relMSE (eps 0.01) against the references, seed 1; ratio = noisy / denoised;\n"
                 "oracle = noisy / the oracle's choice among the filters (bandwidths 0.25-4)\n";
    for (const DenoiserScene &entry : scenes())
        for (int spp : {4, 16, 64})
            measure(entry, spp, threads, writeFolder);
    measure(defaultScene(), 0, threads, writeFolder);

    const RenderResult large = render(scenes()[0], 16, 1, threads, {{"size", "512"}});
    DenoiserSettings settings;
    settings.threads = threads;
    std::vector<double> seconds;
    for (int run = 0; run < 5; ++run) {
        const auto start = std::chrono::steady_clock::now();
        denoise(large.layers, settings);
        seconds.push_back(secondsSince(start));
    }
    std::sort(seconds.begin(), seconds.end());
    std::cout << fmt::format("denoising 512x512 (cbox, 16 spp), {} threads: {:.2f} s "
                             "(median of 5; fastest {:.2f}, slowest {:.2f})\n",
                             threads > 0 ? threads : defaultThreadCount(), seconds[2],
                             seconds.front(), seconds.back());
    return 0;
}

} // namespace

int main(int argc, char **argv) {
    int threads = 0;
    bool makeReferences = false;
    std::string writeFolder, cropsFile;
    return runCommandLine(
        argc, argv, "nori-bench-denoiser",
        "The figures of the denoiser: relMSE of the noisy and denoised images against "
        "converged references, and the time to denoise.",
        [&](CLI::App &app) {
            app.add_option("--threads", threads, "threads (default: all cores)")->type_name("N");
            app.add_option("--write", writeFolder, "also write the images to DIR")
                ->type_name("DIR");
            app.add_option("--crops", cropsFile,
                           "only write FILE.png: noisy, denoised and reference crops of each "
                           "scene side by side (the README's)")
                ->type_name("FILE");
            app.add_flag("--make-references", makeReferences,
                         "render the converged references the tests compare against");
        },
        [&](const CLI::App &) { return run(threads, makeReferences, writeFolder, cropsFile); });
}
