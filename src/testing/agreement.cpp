#include "testing/agreement.h"

#include <nori/common.h>
#include <nori/hash.h>
#include <nori/parallel.h>
#include <nori/parser.h>
#include <nori/render.h>
#include <nori/scene.h>
#include <nori/statistics.h>
#include <nori/testsamples.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <random>
#include <unistd.h>

namespace nori {

namespace {

/// One-sided normal quantile of 95 %: a bias of (threshold + 1.645) standard errors
/// exceeds the threshold in 95 % of runs.
constexpr double kPowerQuantile = 1.645;

/// The factor of every estimator's samples per pixel: the settings' (a soak's 8) times the
/// tests' knob (NORI_TEST_SAMPLE_SCALE, include/nori/testsamples.h).
double samplesFactor(const AgreementSettings &settings) {
    return settings.sampleScale * testSampleScale();
}

/// The bias every comparison must see: with the knob at s the standard errors grow by
/// 1/√s, and the bias asked for with them, as a soak's asks for √8 times less.
double requiredBias(const AgreementSettings &settings) {
    return settings.detectableBias / std::sqrt(testSampleScale());
}

/// A scene's files in a fresh folder under the system's temp folder, removed with it.
class SceneFolder {
public:
    explicit SceneFolder(const AgreementScene &scene) {
        std::random_device entropy;
        m_path = std::filesystem::temp_directory_path() /
                 fmt::format("nori-agreement-{}-{:08x}", getpid(), entropy());
        std::filesystem::create_directories(m_path);
        for (const auto &[name, write] : scene.files)
            write((m_path / name).string());
    }
    ~SceneFolder() {
        std::error_code ignored;
        std::filesystem::remove_all(m_path, ignored);
    }
    SceneFolder(const SceneFolder &) = delete;
    SceneFolder &operator=(const SceneFolder &) = delete;
    std::string path() const { return m_path.string(); }

private:
    std::filesystem::path m_path;
};

/// The mean of a region of the image, over pixels and colour channels.
double regionMean(const Bitmap &image, const ImageRegion &region) {
    const int width = region.width > 0 ? region.width : static_cast<int>(image.cols());
    const int height = region.width > 0 ? region.height : static_cast<int>(image.rows());
    if (region.x < 0 || region.y < 0 || region.x + width > image.cols() ||
        region.y + height > image.rows())
        throw NoriException("region '{}' does not fit in the {}x{} image", region.name,
                            image.cols(), image.rows());
    double sum = 0.0;
    for (int y = region.y; y < region.y + height; ++y)
        for (int x = region.x; x < region.x + width; ++x)
            sum += image(y, x).sum() / 3.0;
    return sum / (static_cast<double>(width) * height);
}

} // namespace

std::vector<RegionEstimate> estimateRegions(const AgreementScene &scene, const Estimator &estimator,
                                            int estimatorIndex, const AgreementSettings &settings) {
    if (settings.batches < 2)
        throw NoriException("agreement: at least 2 batches are needed for a standard error");
    const SceneFolder folder(scene);
    std::vector<ImageRegion> regions{{"image", 0, 0, 0, 0}};
    regions.insert(regions.end(), scene.regions.begin(), scene.regions.end());
    // An estimator exempt from the power requirement is one of rare events (BSDF sampling
    // that seldom finds a small light): its batch means are normal only at its full count
    // (at a tenth, path_mats on the glossy plates was 5.25 standard errors low, its batches
    // skewed by the few that found the light), so the tests' knob leaves it alone.
    const double factor =
        estimator.powerExemption.empty() ? samplesFactor(settings) : settings.sampleScale;
    const size_t spp = std::max<size_t>(
        1,
        static_cast<size_t>(std::llround(factor * static_cast<double>(estimator.samplesPerPixel))));
    // The images are small (one render block, one thread each), so the batches render
    // in parallel; each batch's means are kept and summed in batch order, which keeps the
    // result independent of the thread count.
    std::vector<std::vector<double>> means(static_cast<size_t>(settings.batches));
    std::vector<Bitmap> images(static_cast<size_t>(settings.batches));
    ThreadLimit(settings.threads).run([&] {
        parallelFor(0, settings.batches, [&](int batch) {
            // Independent streams for every (seed, estimator, batch): runs with seeds s and
            // s + 1 share no batch. The sampler's seed is an integer property: 31 bits.
            const uint64_t seed = hashValues(settings.seed, static_cast<uint64_t>(estimatorIndex),
                                             static_cast<uint64_t>(batch)) >>
                                  33;
            const std::string xml = fmt::format(
                "<scene>{}{}<sampler type=\"{}\"><integer name=\"sampleCount\" value=\"{}\"/>"
                "<integer name=\"seed\" value=\"{}\"/>{}</sampler></scene>",
                scene.body, estimator.integrator, estimator.sampler, spp, seed,
                estimator.samplerXML);
            std::shared_ptr<Scene> loaded;
            try {
                loaded = std::dynamic_pointer_cast<Scene>(loadFromXMLString(xml, folder.path()));
            } catch (const NoriException &error) {
                throw NoriException("agreement scene '{}' with {}: {}", scene.name, estimator.label,
                                    error.what());
            }
            if (!loaded)
                throw NoriException("agreement scene '{}' is not a scene", scene.name);
            RenderOptions options;
            options.threads = 1;
            options.samplesPerPixel = spp;
            const RenderResult result = renderScene(*loaded, options);
            for (const ImageRegion &region : regions)
                means[static_cast<size_t>(batch)].push_back(regionMean(result.image, region));
            images[static_cast<size_t>(batch)] = result.image;
        });
    });
    std::vector<RunningMoments> moments(regions.size());
    Bitmap sum = images.front();
    for (size_t batch = 0; batch < means.size(); ++batch) {
        for (size_t r = 0; r < regions.size(); ++r)
            moments[r].add(means[batch][r]);
        if (batch > 0)
            sum += images[batch];
    }
    if (!settings.pictureFolder.empty()) {
        sum /= static_cast<float>(settings.batches);
        std::string stem = scene.name + "-" + estimator.label;
        std::replace_if(
            stem.begin(), stem.end(), [](char c) { return c == '/' || c == '+'; }, '_');
        const std::string path = (std::filesystem::path(settings.pictureFolder) / stem).string();
        sum.saveEXR(path + ".exr");
        sum.savePNG(path + ".png");
    }
    std::vector<RegionEstimate> estimates;
    estimates.reserve(moments.size());
    for (const RunningMoments &m : moments)
        estimates.push_back({m.mean, std::sqrt(m.variance() / static_cast<double>(m.count))});
    return estimates;
}

AgreementCell compareEstimates(const RegionEstimate &estimate, const RegionEstimate &other,
                               const AgreementSettings &settings) {
    AgreementCell cell;
    // The film sums samples in float: two estimators with no variance on a region (an
    // environment map seen directly) still differ by rounding, a few 2^-24 per sample
    // summed; 1e-5 of the mean bounds that for the sample counts used here.
    const double rounding = 1e-5 * std::max(std::abs(estimate.mean), std::abs(other.mean));
    const double sigma =
        std::max(std::hypot(estimate.standardError, other.standardError), rounding);
    const double scale = std::abs(other.mean);
    cell.difference = scale > 0.0 ? (estimate.mean - other.mean) / scale : 0.0;
    // Two estimates that are both exactly zero (an unlit region) agree; any difference
    // with zero variance on both sides is an infinite number of standard errors.
    const double delta = estimate.mean - other.mean;
    cell.z = sigma > 0.0 ? delta / sigma : (delta == 0.0 ? 0.0 : std::copysign(HUGE_VAL, delta));
    cell.detectableBias = scale > 0.0 ? (settings.threshold + kPowerQuantile) * sigma / scale : 0.0;
    cell.agrees = std::abs(cell.z) <= settings.threshold;
    cell.powerful = cell.detectableBias <= requiredBias(settings);
    return cell;
}

AgreementReport runAgreement(const std::vector<AgreementScene> &scenes,
                             const AgreementSettings &settings) {
    const auto start = std::chrono::steady_clock::now();
    AgreementReport report;
    for (const AgreementScene &scene : scenes) {
        auto &perEstimator = report.estimates.emplace_back();
        for (size_t e = 0; e < scene.estimators.size(); ++e) {
            const auto begin = std::chrono::steady_clock::now();
            perEstimator.push_back(
                estimateRegions(scene, scene.estimators[e], static_cast<int>(e), settings));
            if (settings.progress)
                settings.progress(fmt::format(
                    "{}: {} ({:.1f} s)", scene.name, scene.estimators[e].label,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - begin)
                        .count()));
        }
        for (size_t r = 0; r <= scene.regions.size(); ++r) {
            const std::string region = r == 0 ? "image" : scene.regions[r - 1].name;
            for (size_t a = 0; a < scene.estimators.size(); ++a)
                for (size_t b = 0; b < a; ++b) {
                    AgreementCell cell =
                        compareEstimates(perEstimator[a][r], perEstimator[b][r], settings);
                    cell.scene = scene.name;
                    cell.region = region;
                    cell.estimator = scene.estimators[a].label;
                    cell.other = scene.estimators[b].label;
                    cell.powerExemption = !scene.estimators[a].powerExemption.empty()
                                              ? scene.estimators[a].powerExemption
                                              : scene.estimators[b].powerExemption;
                    report.cells.push_back(cell);
                }
        }
    }
    report.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

bool AgreementReport::passed(bool requirePower) const {
    return std::all_of(cells.begin(), cells.end(), [&](const AgreementCell &cell) {
        return cell.agrees && (!requirePower || cell.powerful || !cell.powerExemption.empty());
    });
}

std::string AgreementReport::table(const std::vector<AgreementScene> &scenes,
                                   const AgreementSettings &settings) const {
    std::string out = fmt::format(
        "Differences to each scene's first estimator in standard errors (|z| > {:g} "
        "disagrees: marked !); below each z, in brackets, the smallest bias the comparison "
        "sees with 95 % power (marked ~ when above {:g} %). {} batches per estimator.\n",
        settings.threshold, 100.0 * requiredBias(settings), settings.batches);
    size_t cellIndex = 0;
    for (size_t s = 0; s < scenes.size(); ++s) {
        const AgreementScene &scene = scenes[s];
        out += fmt::format("\n{}: reference {} ({} spp × {}); others:", scene.name,
                           scene.estimators.front().label, scene.estimators.front().samplesPerPixel,
                           settings.batches);
        for (size_t e = 1; e < scene.estimators.size(); ++e)
            out += fmt::format(" {} ({} spp)", scene.estimators[e].label,
                               scene.estimators[e].samplesPerPixel);
        out += "\n";
        out += fmt::format("  {:<12} {:>18}", "region", "reference mean");
        for (size_t e = 1; e < scene.estimators.size(); ++e)
            out += fmt::format(" {:>14.14}", scene.estimators[e].label);
        out += "\n";
        const size_t pairs = scene.estimators.size() * (scene.estimators.size() - 1) / 2;
        for (size_t r = 0; r <= scene.regions.size(); ++r) {
            const RegionEstimate &reference = estimates[s][0][r];
            out += fmt::format("  {:<12} {:>10.5g} ±{:<7.2g}",
                               r == 0 ? "image" : scene.regions[r - 1].name, reference.mean,
                               reference.standardError);
            // The cells of region r come in the order (1,0), (2,0), (2,1), (3,0), ...:
            // the comparison of estimator a with the reference is at a(a−1)/2.
            std::string biases;
            for (size_t a = 1; a < scene.estimators.size(); ++a) {
                const AgreementCell &cell = cells[cellIndex + a * (a - 1) / 2];
                out += fmt::format(" {:>13.2f}{}", cell.z, cell.agrees ? ' ' : '!');
                biases +=
                    fmt::format(" {:>13}{}", fmt::format("[{:.2f}%]", 100.0 * cell.detectableBias),
                                cell.powerful ? ' ' : '~');
            }
            out += fmt::format("\n  {:<12} {:>18}{}\n", "", "", biases);
            cellIndex += pairs;
        }
    }
    size_t disagreeing = 0, weak = 0, exempt = 0;
    for (const AgreementScene &scene : scenes)
        for (const Estimator &estimator : scene.estimators)
            if (!estimator.powerExemption.empty())
                out += fmt::format("{} / {}: not held to the power asked for: {}\n", scene.name,
                                   estimator.label, estimator.powerExemption);
    for (const AgreementCell &cell : cells) {
        if (!cell.agrees) {
            ++disagreeing;
            out += fmt::format("DISAGREE {} / {}: {} and {} differ by {:+.3f} % = {:+.2f} "
                               "standard errors\n",
                               cell.scene, cell.region, cell.estimator, cell.other,
                               100.0 * cell.difference, cell.z);
        }
        if (!cell.powerful && !cell.powerExemption.empty()) {
            ++exempt;
        } else if (!cell.powerful) {
            ++weak;
            out += fmt::format("TOO FEW SAMPLES {} / {}: {} against {} sees biases of {:.2f} "
                               "% or more, not {:g} %\n",
                               cell.scene, cell.region, cell.estimator, cell.other,
                               100.0 * cell.detectableBias, 100.0 * requiredBias(settings));
        }
    }
    out += fmt::format("{} comparisons, {} disagree, {} lack the power for a {:g} % bias "
                       "(and {} more of exempt estimators); {:.1f} s\n",
                       cells.size(), disagreeing, weak, 100.0 * requiredBias(settings), exempt,
                       seconds);
    return out;
}

} // namespace nori
