// nori-lensinfo: what a lens file describes, and how well the realistic camera samples it.
//   nori-lensinfo LENS.dat [--focus METRES] [--aperture MM] [--film-diagonal MM]
//                          [--width PIXELS] [--height PIXELS]
// Prints the effective focal length, cardinal points, nearest focus distance, the film
// distance after focusing, the exit pupil at a few film radii, and the fraction of
// camera rays the lens blocks with exit-pupil sampling and without it.
#include <nori/common.h>
#include <nori/lenssystem.h>
#include <nori/strutil.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

using namespace nori;

namespace {

struct Options {
    std::string lensFile;
    double focus = 10.0, aperture = 0.0, filmDiagonal = 35.0;
    int width = 1280, height = 720;
};

Options parseArguments(int argc, char **argv) {
    Options options;
    for (int i = 1; i < argc; ++i) {
        const std::string argument = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc)
                throw NoriException("{} needs a value", argument);
            return argv[++i];
        };
        if (argument == "--focus")
            options.focus = toFloat(value(), "--focus");
        else if (argument == "--aperture")
            options.aperture = toFloat(value(), "--aperture");
        else if (argument == "--film-diagonal")
            options.filmDiagonal = toFloat(value(), "--film-diagonal");
        else if (argument == "--width")
            options.width = toInt(value(), "--width");
        else if (argument == "--height")
            options.height = toInt(value(), "--height");
        else if (!argument.empty() && argument[0] == '-')
            throw NoriException("unknown option '{}'", argument);
        else if (options.lensFile.empty())
            options.lensFile = argument;
        else
            throw NoriException("one lens file at a time, got '{}' and '{}'", options.lensFile,
                                argument);
    }
    if (options.lensFile.empty())
        throw NoriException("usage: nori-lensinfo LENS.dat [--focus METRES] [--aperture MM] "
                            "[--film-diagonal MM] [--width PIXELS] [--height PIXELS]");
    if (!(options.focus > 0.0 && options.filmDiagonal > 0.0 && options.aperture >= 0.0 &&
          options.width > 0 && options.height > 0))
        throw NoriException("--focus, --film-diagonal, --width and --height must be positive, "
                            "--aperture not negative");
    return options;
}

} // namespace

int main(int argc, char **argv) {
    try {
        const Options options = parseArguments(argc, argv);
        LensSystem lens(readLensFile(options.lensFile), options.aperture, options.lensFile);
        const LensSystem::CardinalPoints points = lens.cardinalPoints();
        std::printf("%s\n", options.lensFile.c_str());
        std::printf("  effective focal length   %.3f mm\n", 1e3 * points.effectiveFocalLength());
        std::printf("  principal planes         front %.3f mm, rear %.3f mm (from the film, "
                    "as written)\n",
                    1e3 * points.frontPrincipalZ, 1e3 * points.rearPrincipalZ);
        std::printf("  nearest focus distance   %.4f m\n", lens.nearestFocusDistance());
        lens.focusAt(options.focus);
        std::printf("  focused at %g m: film %.3f mm behind the rear vertex, lens %.3f mm "
                    "long\n",
                    options.focus, 1e3 * lens.rearZ(), 1e3 * (lens.frontZ() - lens.rearZ()));

        const double diagonal = 1e-3 * options.filmDiagonal;
        const Eigen::Vector2d film = filmExtent(diagonal, options.width, options.height);
        const auto start = std::chrono::steady_clock::now();
        const ExitPupil pupil(lens, 0.5 * diagonal);
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::printf("  exit pupil (tabulated in %.2f s; mm, film point on +x):\n", seconds);
        for (double fraction : {0.0, 0.25, 0.5, 0.75, 1.0}) {
            const double radius = fraction * 0.5 * diagonal;
            const ExitPupil::Region &region = pupil.regionAt(radius);
            std::printf("    film radius %6.2f mm: ellipse centre (%7.3f, %7.3f), semi-axes "
                        "%6.3f x %6.3f\n",
                        1e3 * radius, 1e3 * region.center.x(), 1e3 * region.center.y(),
                        1e3 * region.semiAxes.x(), 1e3 * region.semiAxes.y());
        }
        constexpr int kSamples = 1 << 20;
        const RayLoss withPupil = measureRayLoss(lens, &pupil, film, kSamples);
        const RayLoss withoutPupil = measureRayLoss(lens, nullptr, film, kSamples);
        std::printf("  rays blocked (film %.2f x %.2f mm, %d film points): %.2f%% toward the "
                    "exit pupil, %.2f%% toward the whole rear element; %.2f%% of the film "
                    "gets no light\n",
                    1e3 * film.x(), 1e3 * film.y(), kSamples, 100.0 * withPupil.blocked,
                    100.0 * withoutPupil.blocked, 100.0 * withPupil.unlit);
        return 0;
    } catch (const NoriException &error) {
        std::fprintf(stderr, "Error: %s\n", error.what());
        return 1;
    }
}
