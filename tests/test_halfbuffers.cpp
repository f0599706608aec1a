// The standard error of a region's mean from one render's half-buffers
// (src/testing/halfbuffers.h), and `nori-imgtool compare`, which gives its verdict.
#include "testutil.h"

#include "testing/agreementscenes.h"
#include "testing/halfbuffers.h"

#include <nori/render.h>
#include <nori/scene.h>
#include <nori/statistics.h>

#include <catch2/catch.hpp>

#include <algorithm>

using namespace nori;

namespace {

/// The matrix's Cornell box (32×32, Gaussian filter), its files written to `dir`.
AgreementScene cornellBox(const nori::testing::TempDir &dir) {
    std::vector<AgreementScene> scenes = agreementMatrixScenes();
    const auto found = std::find_if(scenes.begin(), scenes.end(), [](const AgreementScene &s) {
        return s.name == "cornell-box";
    });
    REQUIRE(found != scenes.end());
    for (const auto &[name, write] : found->files)
        write((dir.path() / name).string());
    return *found;
}

/// One path_mis render of `scene` with the variance layer (and so the half-buffers).
LayeredImage renderWithHalves(const AgreementScene &scene, const nori::testing::TempDir &dir,
                              int seed, size_t spp) {
    const std::string xml = fmt::format(
        R"(<scene>{}<integrator type="path_mis"/><sampler type="independent">
           <integer name="sampleCount" value="{}"/><integer name="seed" value="{}"/></sampler></scene>)",
        scene.body, spp, seed);
    const std::shared_ptr<Scene> loaded = nori::testing::loadScene(xml, dir.path().string());
    RenderOptions options = nori::testing::quietOptions(1);
    options.aovs = {AOV::Variance};
    return renderScene(*loaded, options).layers;
}

/// The two-sided p-value of (n − 1)·s²/σ², which is χ²(n − 1) when σ² is the variance.
double varianceRatioPValue(double sampleVariance, double predictedVariance, int n) {
    const double statistic = (n - 1) * sampleVariance / predictedVariance;
    const double cdf = chiSquareCdf(statistic, n - 1);
    return 2.0 * std::min(cdf, 1.0 - cdf);
}

} // namespace

TEST_CASE("Half-buffer standard errors match the spread of region means over seeds",
          "[agreement][halfbuffers]") {
    // 48 renders of the Cornell box at 16 spp: the variance of a region's mean over the
    // seeds must match the mean of the variances each render predicts, by a χ² test on
    // 47 degrees of freedom at a significance of 10⁻³. Negative control: the variance
    // layer summed over the region (each pixel's own variance, correlations through the
    // Gaussian filter left out) predicts too little and is rejected.
    nori::testing::TempDir dir;
    const AgreementScene scene = cornellBox(dir);
    const std::vector<ImageRegion> regions = {
        {"image", 0, 0, 0, 0}, {"red-wall", 0, 8, 4, 12}, {"floor", 4, 24, 24, 8}};
    constexpr int kSeeds = 48;
    std::vector<RunningMoments> means(regions.size());
    std::vector<double> predicted(regions.size(), 0.0), layerSums(regions.size(), 0.0);
    double correlation = 0.0;
    for (int seed = 1; seed <= kSeeds; ++seed) {
        const LayeredImage render = renderWithHalves(scene, dir, seed, 16);
        const HalfBufferErrors errors(render);
        correlation += errors.correlationFactor() / kSeeds;
        const Bitmap variance = render.layer("variance");
        for (size_t r = 0; r < regions.size(); ++r) {
            const RegionEstimate green = errors.estimate(regions[r])[1];
            means[r].add(green.mean);
            predicted[r] += green.standardError * green.standardError / kSeeds;
            const ImageRegion &region = regions[r];
            const int w = region.width > 0 ? region.width : int(variance.cols());
            const int h = region.width > 0 ? region.height : int(variance.rows());
            double sum = 0.0;
            for (int y = region.y; y < region.y + h; ++y)
                for (int x = region.x; x < region.x + w; ++x)
                    sum += variance(y, x).g();
            layerSums[r] += sum / (double(w) * h * w * h) / kSeeds;
        }
    }
    for (size_t r = 0; r < regions.size(); ++r) {
        const double observed = means[r].variance();
        const double p = varianceRatioPValue(observed, predicted[r], kSeeds);
        const double pLayer = varianceRatioPValue(observed, layerSums[r], kSeeds);
        INFO(regions[r].name << ": standard deviation over seeds " << std::sqrt(observed)
                             << ", predicted " << std::sqrt(predicted[r]) << " (p = " << p
                             << "), variance layer alone " << std::sqrt(layerSums[r])
                             << " (p = " << pLayer << "); mean κ " << correlation);
        CHECK(p > 1e-3);
        CHECK(pLayer < 1e-3);
    }
}

TEST_CASE("Half-buffer errors need the half-buffers, two samples and room for tiles",
          "[agreement][halfbuffers]") {
    nori::testing::TempDir dir;
    const AgreementScene scene = cornellBox(dir);
    LayeredImage render = renderWithHalves(scene, dir, 1, 4);
    CHECK(hasHalfBuffers(render));
    CHECK_NOTHROW(HalfBufferErrors(render));

    const LayeredImage oneSample = renderWithHalves(scene, dir, 1, 1);
    CHECK_THAT(nori::testing::errorOf([&] { HalfBufferErrors errors(oneSample); }),
               Catch::Contains("has no sample in one of its half-buffers"));

    LayeredImage beautyOnly(render.size());
    beautyOnly.addLayer("", {"R", "G", "B"}, render.layer(""));
    CHECK_FALSE(hasHalfBuffers(beautyOnly));
    CHECK_THAT(nori::testing::errorOf([&] { HalfBufferErrors errors(beautyOnly); }),
               Catch::Contains("render it with the variance layer"));

    CHECK_THAT(nori::testing::errorOf([] {
                   parseImageRegion("r", "30,0,4,4", {32, 32});
               }),
               Catch::Contains("region 'r' (30,0,4,4) does not fit in the 32x32 image"));
    CHECK_THAT(nori::testing::errorOf([] {
                   parseImageRegion("r", "1,2,3", {32, 32});
               }),
               Catch::Contains("expected X,Y,W,H"));
}

TEST_CASE("nori-imgtool compare agrees on two seeds and names a 2 % brighter light",
          "[agreement][halfbuffers][imgtool]") {
    nori::testing::TempDir dir;
    const AgreementScene scene = cornellBox(dir);
    AgreementScene brighter = scene;
    const std::string light = R"(<color name="radiance" value="5"/>)";
    const size_t at = brighter.body.find(light);
    REQUIRE(at != std::string::npos);
    brighter.body.replace(at, light.size(), R"(<color name="radiance" value="5.1"/>)");

    const auto save = [&](const LayeredImage &image, const std::string &name) {
        std::string path = (dir.path() / name).string();
        image.saveEXR(path);
        return path;
    };
    const std::string a = save(renderWithHalves(scene, dir, 1, 1024), "a.exr");
    const std::string b = save(renderWithHalves(scene, dir, 2, 1024), "b.exr");
    const std::string bright = save(renderWithHalves(brighter, dir, 2, 1024), "bright.exr");

    const auto same = nori::testing::runCommand(
        IMGTOOL_EXECUTABLE, {"compare", a, b, "--region", "wall=0,8,4,12", "--grid", "2"});
    INFO(same.output);
    CHECK(same.exitCode == 0);
    CHECK_THAT(same.output, Catch::Contains("verdict: agree") && Catch::Contains("wall ") &&
                                Catch::Contains("cell1,1 "));

    const auto differ = nori::testing::runCommand(IMGTOOL_EXECUTABLE, {"compare", bright, a});
    INFO(differ.output);
    CHECK(differ.exitCode == 1);
    CHECK_THAT(differ.output,
               Catch::Contains("verdict: DISAGREE") && Catch::Contains("(worst: image "));

    // A reference without half-buffers is taken as exact; two such files are an error.
    LayeredImage exact(Eigen::Vector2i(32, 32));
    exact.addLayer("", {"R", "G", "B"}, LayeredImage::loadEXR(a).layer(""));
    const std::string reference = save(exact, "reference.exr");
    const auto againstExact =
        nori::testing::runCommand(IMGTOOL_EXECUTABLE, {"compare", b, reference});
    CHECK_THAT(againstExact.output, Catch::Contains("taken as exact"));
    const auto neither =
        nori::testing::runCommand(IMGTOOL_EXECUTABLE, {"compare", reference, reference});
    CHECK(neither.exitCode == 1);
    CHECK_THAT(neither.output, Catch::Contains("neither"));
    const auto outside =
        nori::testing::runCommand(IMGTOOL_EXECUTABLE, {"compare", a, b, "--region", "r=0,0,40,4"});
    CHECK(outside.exitCode == 1);
    CHECK_THAT(outside.output, Catch::Contains("does not fit in the 32x32 image"));
}
