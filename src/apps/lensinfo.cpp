// nori-lensinfo: what a lens file describes, and how well the realistic camera samples it.
// Prints the effective focal length, cardinal points, nearest focus distance, the film
// distance after focusing, the exit pupil at a few film radii, and the fraction of
// camera rays the lens blocks with exit-pupil sampling and without it.
#include "app/cli.h"
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

void checkOptions(const Options &options) {
    if (!(options.focus > 0.0 && options.filmDiagonal > 0.0 && options.aperture >= 0.0 &&
          options.width > 0 && options.height > 0))
        throw NoriException("--focus, --film-diagonal, --width and --height must be positive, "
                            "--aperture not negative");
}

/// Prints what the lens is and how well the camera samples it.
int report(const Options &options) {
    checkOptions(options);
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
}

} // namespace

int main(int argc, char **argv) {
    Options options;
    return runCommandLine(
        argc, argv, "nori-lensinfo",
        "What a lens file describes, and how well the realistic camera samples it: the "
        "effective focal length, cardinal points, nearest focus distance, the film distance "
        "after focusing, the exit pupil at a few film radii, and the fraction of camera rays "
        "the lens blocks with exit-pupil sampling and without it.",
        [&](CLI::App &app) {
            app.add_option("lens", options.lensFile, "the lens file (pbrt's tabular format)")
                ->type_name("LENS.dat")
                ->required();
            app.add_option("--focus", options.focus, "focus distance from the film (default 10)")
                ->type_name("METRES");
            app.add_option("--aperture", options.aperture,
                           "diameter of the iris (default 0: the lens file's)")
                ->type_name("MM");
            app.add_option("--film-diagonal", options.filmDiagonal,
                           "the film's diagonal (default 35)")
                ->type_name("MM");
            app.add_option("--width", options.width, "image width (default 1280)")
                ->type_name("PIXELS");
            app.add_option("--height", options.height, "image height (default 720)")
                ->type_name("PIXELS");
        },
        [&](const CLI::App &) { return report(options); });
}
