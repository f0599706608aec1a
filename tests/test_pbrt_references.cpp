// The pbrt-v4 importer against pbrt-v4 itself: grey scenes (tests/data/pbrt), one per kind
// of mapping (materials, lights, shapes, textures, a medium, instances, the camera),
// rendered by pbrt-v4 with seeds 1..8 (tests/data/pbrt/refs, made by make-references.sh)
// and here with seeds 1..8. On grey scenes spectral and RGB transport agree, so the two
// renderers must agree within statistics: on the whole image and on every cell of a 4 × 4
// grid, per channel, the difference of the means is within 4 standard errors of the
// difference (Welch's t-test on the seeds' means, at the two-sided level of 4 normal
// standard errors, 6.3·10⁻⁵).
#include <nori/imagefile.h>
#include <nori/parser.h>
#include <nori/pbrtimport.h>
#include <nori/render.h>
#include <nori/statistics.h>

#include "testutil.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <functional>

using namespace nori;
using namespace nori::testing;

namespace {

const std::string kGreyScenes = std::string(NORI_SOURCE_DIR) + "/tests/data/pbrt";
constexpr int kReferenceSeeds = 8;
constexpr size_t kReferenceSpp = 128;
/// The two-sided tail of 4 standard errors of a normal distribution: 2·Φ(−4).
constexpr double kReferenceLevel = 6.334e-5;

/// Per region (the image, then the 16 cells of a 4 × 4 grid, row by row) and channel:
/// the mean of each render.
using GridMeans = std::vector<std::array<double, 3>>;

GridMeans gridMeans(const Bitmap &image) {
    GridMeans means;
    const int w = image.width(), h = image.height();
    auto mean = [&](int x0, int y0, int x1, int y1) {
        std::array<double, 3> sum = {0.0, 0.0, 0.0};
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x)
                for (int c = 0; c < 3; ++c)
                    sum[size_t(c)] += double(image(y, x)[c]);
        const double count = double((x1 - x0) * (y1 - y0));
        for (double &value : sum)
            value /= count;
        return sum;
    };
    means.push_back(mean(0, 0, w, h));
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i)
            means.push_back(mean(i * w / 4, j * h / 4, (i + 1) * w / 4, (j + 1) * h / 4));
    return means;
}

std::string gridRegionName(size_t region) {
    return region == 0 ? "image" : fmt::format("cell{},{}", (region - 1) % 4, (region - 1) / 4);
}

/// Our renders of a pbrt-v4 file, one per seed, through the importer and the XML loader.
/// `edit` may change the XML (the negative controls plant a mapping bug there).
std::vector<GridMeans> renderImported(const std::string &scene,
                                      const std::function<std::string(std::string)> &edit = {}) {
    std::vector<GridMeans> renders;
    const TempDir sideFiles;
    for (int seed = 1; seed <= kReferenceSeeds; ++seed) {
        pbrt::Scene parsed = pbrt::readScene(fmt::format("{}/{}.pbrt", kGreyScenes, scene));
        pbrt::Parameter seedParameter;
        seedParameter.type = "integer";
        seedParameter.name = "seed";
        seedParameter.numbers = {double(seed)};
        parsed.sampler.parameters.push_back(seedParameter);
        pbrt::ConvertOptions options;
        options.sceneDirectory = kGreyScenes;
        options.xmlDirectory = kGreyScenes;
        options.sideFileDirectory = sideFiles.path().string();
        std::string xml = pbrt::convertScene(parsed, options).xml;
        if (edit)
            xml = edit(xml);
        std::shared_ptr<Scene> ours = loadScene(xml, kGreyScenes);
        RenderOptions renderOptions = quietOptions(0);
        renderOptions.samplesPerPixel = kReferenceSpp;
        renders.push_back(gridMeans(renderScene(*ours, renderOptions).layers.layer("")));
    }
    return renders;
}

std::vector<GridMeans> pbrtRenders(const std::string &scene) {
    std::vector<GridMeans> renders;
    for (int seed = 1; seed <= kReferenceSeeds; ++seed)
        renders.push_back(gridMeans(
            readImageFile(fmt::format("{}/refs/{}-seed{}.exr", kGreyScenes, scene, seed)).pixels));
    return renders;
}

struct GridVerdict {
    int failures = 0;
    double worstP = 1.0;
    std::string worst, report;
};

/// Welch's t-test of every region and channel: the seeds' means of one renderer against
/// the other's.
GridVerdict compareGrids(const std::vector<GridMeans> &ours, const std::vector<GridMeans> &theirs) {
    GridVerdict verdict;
    for (size_t region = 0; region < ours.front().size(); ++region)
        for (size_t c = 0; c < 3; ++c) {
            auto moments = [&](const std::vector<GridMeans> &renders) {
                double mean = 0.0, variance = 0.0;
                for (const GridMeans &render : renders)
                    mean += render[region][c];
                mean /= double(renders.size());
                for (const GridMeans &render : renders)
                    variance += (render[region][c] - mean) * (render[region][c] - mean);
                variance /= double(renders.size() - 1);
                return std::make_pair(mean, variance / double(renders.size()));
            };
            const auto [meanA, seA2] = moments(ours);
            const auto [meanB, seB2] = moments(theirs);
            const double se2 = seA2 + seB2;
            double p = 1.0;
            if (se2 > 0.0) {
                const double t = (meanA - meanB) / std::sqrt(se2);
                // Welch–Satterthwaite degrees of freedom.
                const double nA = double(ours.size() - 1), nB = double(theirs.size() - 1);
                const double dof = se2 * se2 / (seA2 * seA2 / nA + seB2 * seB2 / nB);
                p = 2.0 * (1.0 - studentTCdf(std::abs(t), dof));
            } else if (meanA != meanB) {
                p = 0.0;
            }
            const std::string line =
                fmt::format("{} {}: ours {:.6g}, pbrt-v4 {:.6g} (SE of the difference {:.3g}), "
                            "p = {:.3g}\n",
                            gridRegionName(region), "RGB"[c], meanA, meanB, std::sqrt(se2), p);
            verdict.report += line;
            if (p < verdict.worstP) {
                verdict.worstP = p;
                verdict.worst = line;
            }
            if (p < kReferenceLevel)
                ++verdict.failures;
        }
    return verdict;
}

} // namespace

TEST_CASE("grey pbrt-v4 scenes render as pbrt-v4 renders them", "[pbrt][reference]") {
    for (const char *scene :
         {"cornell-grey", "materials-grey", "lights-grey", "textures-grey", "shapes-grey",
          "medium-grey", "instances-grey", "camera-grey", "film-grey"}) {
        INFO(scene);
        const GridVerdict verdict = compareGrids(renderImported(scene), pbrtRenders(scene));
        INFO(verdict.report);
        INFO("worst: " << verdict.worst);
        CHECK(verdict.failures == 0);
    }
}

TEST_CASE("the pbrt-v4 reference comparison rejects a planted mapping bug",
          "[pbrt][reference][negative]") {
    const std::vector<GridMeans> references = pbrtRenders("cornell-grey");
    SECTION("a light 3% too bright") {
        const GridVerdict verdict =
            compareGrids(renderImported("cornell-grey",
                                        [](std::string xml) {
                                            const std::string from = "\"30, 30, 30\"";
                                            REQUIRE(xml.find(from) != std::string::npos);
                                            return xml.replace(xml.find(from), from.size(),
                                                               "\"30.9, 30.9, 30.9\"");
                                        }),
                         references);
        CHECK(verdict.failures > 0);
    }
    SECTION("fov on the horizontal axis instead of the shorter one") {
        const GridVerdict verdict =
            compareGrids(renderImported("cornell-grey",
                                        [](std::string xml) {
                                            const size_t at = xml.find("name=\"fov\" value=\"");
                                            REQUIRE(at != std::string::npos);
                                            const size_t begin = at + 18;
                                            const size_t end = xml.find('"', begin);
                                            return xml.replace(begin, end - begin, "37.5");
                                        }),
                         references);
        CHECK(verdict.failures > 0);
    }
}

TEST_CASE("the pbrt-v4 reference comparison rejects a planted film mapping bug",
          "[pbrt][reference][negative]") {
    const std::vector<GridMeans> references = pbrtRenders("film-grey");
    SECTION("no white balance") {
        const GridVerdict verdict =
            compareGrids(renderImported("film-grey",
                                        [](std::string xml) {
                                            const std::string from =
                                                "<float name=\"whiteBalance\" value=\"3200\" />";
                                            REQUIRE(xml.find(from) != std::string::npos);
                                            return xml.replace(xml.find(from), from.size(), "");
                                        }),
                         references);
        CHECK(verdict.failures > 0);
    }
    SECTION("the crop one pixel to the right") {
        const GridVerdict verdict = compareGrids(
            renderImported("film-grey",
                           [](std::string xml) {
                               const std::string from =
                                   "<integer name=\"cropOffsetX\" value=\"8\" />";
                               REQUIRE(xml.find(from) != std::string::npos);
                               return xml.replace(xml.find(from), from.size(),
                                                  "<integer name=\"cropOffsetX\" value=\"9\" />");
                           }),
            references);
        CHECK(verdict.failures > 0);
    }
}
