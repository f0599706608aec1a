// nori-bench-denoiser: the figures of the denoiser.
//   1. relMSE against converged references of the noisy and the denoised image at 4,
//      16 and 64 spp (and of the noisy image at 256 spp) on the Cornell box, Veach's
//      MIS scene and the textured scene (tests/denoiser_scenes.h), seed 1.
//   2. The time to denoise a 512×512 render of the Cornell box, best of 3.
//
//   nori-bench-denoiser [--threads N] [--write DIR]   (DIR: the images, as PFM and PNG)
//   nori-bench-denoiser --make-references   (renders tests/data/denoiser/*.exr)
#include "app/cli.h"
#include "denoise/denoiser.h"
#include <nori/render.h>
#include <nori/scene.h>
#include <nori/strutil.h>

#include <denoiser_scenes.h>

#include <chrono>
#include <iostream>

using namespace nori;
using namespace nori::denoiserscenes;

namespace {

const std::string kSourceDir = NORI_SOURCE_DIR;

RenderResult render(const DenoiserScene &entry, int spp, int seed, int threads,
                    const Defines &overrides = {}) {
    auto scene = load(entry, kSourceDir, spp, seed, overrides);
    RenderOptions options;
    options.threads = threads;
    options.aovs = denoiserAOVs();
    return renderScene(*scene, options);
}

std::string referencePath(const DenoiserScene &entry) {
    return kSourceDir + "/tests/data/denoiser/" + entry.name + ".exr";
}

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

int run(int threads, bool makeReferences, const std::string &writeFolder) {
    if (makeReferences) {
        for (const DenoiserScene &entry : scenes()) {
            const RenderResult reference = render(entry, kReferenceSpp, 0, threads);
            reference.image.saveEXR(referencePath(entry));
            std::cout << fmt::format("{}: {} spp in {:.1f} s -> {}\n", entry.name, kReferenceSpp,
                                     reference.seconds, referencePath(entry));
        }
        return 0;
    }

    DenoiserSettings settings;
    settings.threads = threads;
    std::cout << "relMSE (eps 0.01) against the references, seed 1; ratio = noisy / denoised\n";
    for (const DenoiserScene &entry : scenes()) {
        const Bitmap reference = Bitmap::load(referencePath(entry));
        for (int spp : {4, 16, 64}) {
            const RenderResult noisy = render(entry, spp, 1, threads);
            const auto start = std::chrono::steady_clock::now();
            const Bitmap denoised = denoise(noisy.layers, settings);
            const double seconds = secondsSince(start);
            const double before = relativeMeanSquaredError(noisy.image, reference);
            const double after = relativeMeanSquaredError(denoised, reference);
            if (!writeFolder.empty()) {
                const std::string stem = fmt::format("{}/{}_{}", writeFolder, entry.name, spp);
                for (const auto &[suffix, image] : {std::pair{"", &noisy.image},
                                                    {"_denoised", &denoised},
                                                    {"_reference", &reference}}) {
                    image->savePFM(stem + suffix + ".pfm");
                    image->savePNG(stem + suffix + ".png");
                }
            }
            std::cout << fmt::format("{:<9} {:>3} spp  noisy {:.3e}  denoised {:.3e}  ratio "
                                     "{:5.1f}  ({:.2f} s)\n",
                                     entry.name, spp, before, after, before / after, seconds);
        }
        const RenderResult noisy256 = render(entry, 256, 1, threads);
        std::cout << fmt::format("{:<9} 256 spp  noisy {:.3e}\n", entry.name,
                                 relativeMeanSquaredError(noisy256.image, reference));
    }

    const RenderResult large = render(scenes()[0], 16, 1, threads, {{"size", "512"}});
    double best = 1e30;
    for (int run = 0; run < 3; ++run) {
        const auto start = std::chrono::steady_clock::now();
        denoise(large.layers, settings);
        best = std::min(best, secondsSince(start));
    }
    std::cout << fmt::format("denoising 512x512 (cbox, 16 spp): {:.2f} s (best of 3, {} threads)\n",
                             best, threads > 0 ? threads : defaultThreadCount());
    return 0;
}

} // namespace

int main(int argc, char **argv) {
    int threads = 0;
    bool makeReferences = false;
    std::string writeFolder;
    return runCommandLine(
        argc, argv, "nori-bench-denoiser",
        "The figures of the denoiser: relMSE of the noisy and denoised images against "
        "converged references, and the time to denoise.",
        [&](CLI::App &app) {
            app.add_option("--threads", threads, "threads (default: all cores)")->type_name("N");
            app.add_option("--write", writeFolder, "also write the images to DIR")
                ->type_name("DIR");
            app.add_flag("--make-references", makeReferences,
                         "render the converged references the tests compare against");
        },
        [&](const CLI::App &) { return run(threads, makeReferences, writeFolder); });
}
