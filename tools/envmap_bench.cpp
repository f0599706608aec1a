// nori-bench-envmap: the figures of environment-map lighting.
//   1. The time to build the sampling distribution of a 4096×2048 map (Distribution2D over
//      luminance × sin θ), and to load such a map as an `envmap` (decode, MIP pyramid,
//      distribution).
//   2. The RMSE at equal samples per pixel of path_mis on scenes/envmap/envmap.xml with
//      importance sampling against uniform sphere sampling of the map, both against a
//      high-spp reference.
//
//   nori-bench-envmap [--spp N] [--reference-spp N] [--width W --height H]
#include "app/cli.h"
#include <nori/bitmap.h>
#include <nori/dpdf.h>
#include <nori/emitter.h>
#include <nori/parser.h>
#include <nori/render.h>
#include <nori/scene.h>
#include <nori/strutil.h>

#include <chrono>
#include <filesystem>
#include <iostream>

using namespace nori;

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// A 4096×2048 sky-like map: a gradient with a sun, the kind of map the figure is about.
Bitmap largeMap() {
    constexpr int width = 4096, height = 2048;
    Bitmap map(Eigen::Vector2i(width, height));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const float up = 1.0f - float(y) / height;
            const bool sun = std::abs(x - 1200) < 12 && std::abs(y - 600) < 12;
            map(y, x) = sun ? Color3f(5000.0f) : Color3f(0.2f + up, 0.3f + up, 0.6f + up);
        }
    return map;
}

void distributionFigures() {
    const Bitmap map = largeMap();
    std::vector<float> weights(static_cast<size_t>(map.width()) * map.height());
    for (int y = 0; y < map.height(); ++y) {
        const float sinTheta = std::sin((y + 0.5f) * kPi / map.height());
        for (int x = 0; x < map.width(); ++x)
            weights[static_cast<size_t>(y) * map.width() + x] = map(y, x).getLuminance() * sinTheta;
    }
    auto start = std::chrono::steady_clock::now();
    const Distribution2D distribution(weights, map.width(), map.height());
    const double buildSeconds = secondsSince(start);

    const std::filesystem::path file =
        std::filesystem::temp_directory_path() / "nori-bench-envmap-4096x2048.exr";
    map.saveEXR(file.string());
    start = std::chrono::steady_clock::now();
    auto envmap = loadFromXMLString(fmt::format(
        R"(<emitter type="envmap"><string name="filename" value="{}"/></emitter>)", file.string()));
    const double loadSeconds = secondsSince(start);
    std::filesystem::remove(file);
    std::cout << fmt::format("distribution of a 4096x2048 map (luminance x sin theta): {:.3f} s\n"
                             "envmap of a 4096x2048 EXR (decode, MIP pyramid, distribution): "
                             "{:.3f} s\n",
                             buildSeconds, loadSeconds);
}

Bitmap renderEnvmapScene(const std::string &sampling, int spp, int width, int height) {
    const std::string scene = std::string(NORI_SOURCE_DIR) + "/scenes/envmap/envmap.xml";
    auto root = std::dynamic_pointer_cast<Scene>(
        loadFromXML(scene, LoadOptions(Defines{{"sampling", sampling},
                                               {"spp", std::to_string(spp)},
                                               {"width", std::to_string(width)},
                                               {"height", std::to_string(height)}})));
    RenderOptions options;
    return renderScene(*root, options).image;
}

void rmseFigures(int spp, int referenceSpp, int width, int height) {
    auto start = std::chrono::steady_clock::now();
    const Bitmap reference = renderEnvmapScene("luminance", referenceSpp, width, height);
    std::cout << fmt::format("reference: {}x{}, {} spp, importance sampling ({:.1f} s)\n", width,
                             height, referenceSpp, secondsSince(start));
    double errors[2];
    const char *names[2] = {"luminance", "uniform"};
    for (int i = 0; i < 2; ++i) {
        start = std::chrono::steady_clock::now();
        errors[i] =
            std::sqrt(meanSquaredError(renderEnvmapScene(names[i], spp, width, height), reference));
        std::cout << fmt::format("path_mis at {} spp, {} sampling: RMSE {:.5f} ({:.1f} s)\n", spp,
                                 names[i], errors[i], secondsSince(start));
    }
    std::cout << fmt::format("RMSE ratio uniform / importance at equal spp: {:.2f}\n",
                             errors[1] / errors[0]);
}

int run(int spp, int referenceSpp, int width, int height) {
    if (spp < 1 || referenceSpp < 1 || width < 1 || height < 1)
        throw NoriException("spp, sizes must be positive");
    distributionFigures();
    rmseFigures(spp, referenceSpp, width, height);
    return 0;
}

} // namespace

int main(int argc, char **argv) {
    int spp = 16, referenceSpp = 2048, width = 240, height = 135;
    return runCommandLine(
        argc, argv, "nori-bench-envmap",
        "The figures of environment-map lighting: the distribution's build time, and the RMSE "
        "of importance against uniform sampling.",
        [&](CLI::App &app) {
            app.add_option("--spp", spp, "samples per pixel of the compared renders (default 16)")
                ->type_name("N");
            app.add_option("--reference-spp", referenceSpp, "of the reference (default 2048)")
                ->type_name("N");
            app.add_option("--width", width, "image width (default 240)")->type_name("W");
            app.add_option("--height", height, "image height (default 135)")->type_name("H");
        },
        [&](const CLI::App &) { return run(spp, referenceSpp, width, height); });
}
