#include "app/renderpart.h"
#include <nori/aov.h>
#include <nori/camera.h>
#include <nori/film.h>
#include <nori/hash.h>
#include <nori/rfilter.h>
#include <nori/sampler.h>
#include <nori/scene.h>
#include <nori/strutil.h>

#include <algorithm>
#include <charconv>
#include <optional>

namespace nori {

namespace {

const char *const kPartAttribute = "nori.part";
const char *const kHashAttribute = "nori.sceneHash";
const char *const kResolutionAttribute = "nori.resolution";
const char *const kSppAttribute = "nori.spp";
const char *const kSamplesAttribute = "nori.samples";
const char *const kFilterAttribute = "nori.filter";
const char *const kSceneAttribute = "nori.scene";

/// A whole non-negative decimal number, or nothing (no sign, no spaces, no overflow).
std::optional<uint64_t> parseCount(const std::string &text) {
    uint64_t value = 0;
    const char *end = text.data() + text.size();
    const auto [stop, error] = std::from_chars(text.data(), end, value);
    if (text.empty() || error != std::errc() || stop != end)
        return std::nullopt;
    return value;
}

/// "A/B", "AxB" or "A-B": two whole numbers around `separator`.
std::optional<std::pair<uint64_t, uint64_t>> parsePair(const std::string &text, char separator) {
    const size_t at = text.find(separator);
    if (at == std::string::npos)
        return std::nullopt;
    const auto first = parseCount(text.substr(0, at)), second = parseCount(text.substr(at + 1));
    if (!first || !second)
        return std::nullopt;
    return std::make_pair(*first, *second);
}

/// The layer of a channel: "albedo" for "albedo.R", "" (the beauty) for "R".
std::string layerOf(const std::string &channel) {
    const size_t dot = channel.rfind('.');
    return dot == std::string::npos ? std::string() : channel.substr(0, dot);
}

/// How the merge combines a channel over the parts.
enum class MergeRule {
    Weighted,   ///< a filtered mean: Σ value·weight / Σ weight
    EvenHalf,   ///< the even half-buffer's mean, weighted by its own weight
    Summed,     ///< the weights themselves, and sample counts
    Recomputed, ///< the variance, from the merged half-buffers
};

MergeRule mergeRule(const std::string &channel) {
    const std::string layer = layerOf(channel);
    if (channel == kWeightChannel || channel == kEvenHalfWeightChannel ||
        layer == aovName(AOV::SampleCount))
        return MergeRule::Summed;
    if (layer == kEvenHalfLayer)
        return MergeRule::EvenHalf;
    if (layer == aovName(AOV::Variance))
        return MergeRule::Recomputed;
    return MergeRule::Weighted;
}

std::string describeChannels(const LayeredImage &image) {
    std::vector<std::string> names;
    for (const auto &[name, values] : image.channels())
        names.push_back(name);
    return fmt::format("{}", fmt::join(names, ", "));
}

} // namespace

PartSpec parsePartSpec(const std::string &text, const std::string &where) {
    const auto pair = parsePair(text, '/');
    if (!pair || pair->first < 1 || pair->first > pair->second || pair->second > 1u << 20)
        throw NoriException("{} expects K/N with 1 <= K <= N <= {} (part K of N), got '{}'", where,
                            1u << 20, text);
    return {static_cast<int>(pair->first), static_cast<int>(pair->second)};
}

SampleSlice partSamples(const PartSpec &part, size_t totalSpp) {
    if (static_cast<size_t>(part.count) > totalSpp)
        throw NoriException("cannot split {} samples per pixel into {} parts: a part would take "
                            "no sample (use at most {} parts, or more samples)",
                            totalSpp, part.count, totalSpp);
    const auto boundary = [&](int k) {
        return static_cast<uint32_t>(static_cast<uint64_t>(k) * totalSpp /
                                     static_cast<uint64_t>(part.count));
    };
    const uint32_t first = boundary(part.index - 1);
    return {first, boundary(part.index) - first};
}

std::string sceneHash(const std::set<uint64_t> &fileDigests,
                      const std::map<std::string, std::string> &defines,
                      const std::string &convention) {
    std::string identity;
    for (uint64_t digest : fileDigests)
        identity += fmt::format("file {:016x}\n", digest);
    for (const auto &[name, value] : defines) // sorted by name
        identity += fmt::format("define {}={}\n", name, value);
    identity += "camera-convention " + convention + "\n";
    return fmt::format("{:016x}", hashBytes(identity));
}

void writePartHeader(const PartHeader &header, LayeredImage &image) {
    image.attributes[kPartAttribute] = fmt::format("{}/{}", header.part.index, header.part.count);
    image.attributes[kHashAttribute] = header.sceneHash;
    image.attributes[kResolutionAttribute] =
        fmt::format("{}x{}", header.resolution.x(), header.resolution.y());
    image.attributes[kSppAttribute] = std::to_string(header.totalSamplesPerPixel);
    image.attributes[kSamplesAttribute] = fmt::format(
        "{}-{}", header.samples.first, uint64_t(header.samples.first) + header.samples.count);
    image.attributes[kFilterAttribute] = header.filter;
    image.attributes[kSceneAttribute] = header.scene;
}

PartHeader readPartHeader(const LayeredImage &image, const std::string &file) {
    const auto attribute = [&](const char *name) -> const std::string & {
        const auto found = image.attributes.find(name);
        if (found == image.attributes.end())
            throw NoriException("{}: not a part of a split render (its header has no '{}'; "
                                "parts are written by nori --part K/N)",
                                file, name);
        return found->second;
    };
    PartHeader header;
    header.part = parsePartSpec(attribute(kPartAttribute), file + ": header attribute nori.part");
    header.sceneHash = attribute(kHashAttribute);
    const auto resolution = parsePair(attribute(kResolutionAttribute), 'x');
    if (!resolution || resolution->first != static_cast<uint64_t>(image.size().x()) ||
        resolution->second != static_cast<uint64_t>(image.size().y()))
        throw NoriException("{}: header attribute {} is '{}', but the image is {}x{}", file,
                            kResolutionAttribute, attribute(kResolutionAttribute), image.size().x(),
                            image.size().y());
    header.resolution = image.size();
    const auto spp = parseCount(attribute(kSppAttribute));
    if (!spp || *spp == 0 || *spp > UINT32_MAX)
        throw NoriException("{}: header attribute {} is '{}', not a sample count", file,
                            kSppAttribute, attribute(kSppAttribute));
    header.totalSamplesPerPixel = *spp;
    if (header.totalSamplesPerPixel < static_cast<size_t>(header.part.count))
        throw NoriException("{}: part {}/{} of a render of only {} spp", file, header.part.index,
                            header.part.count, header.totalSamplesPerPixel);
    header.samples = partSamples(header.part, header.totalSamplesPerPixel);
    const std::string expectedSamples = fmt::format(
        "{}-{}", header.samples.first, uint64_t(header.samples.first) + header.samples.count);
    if (attribute(kSamplesAttribute) != expectedSamples)
        throw NoriException("{}: header attribute {} is '{}', but part {}/{} of {} spp takes "
                            "samples {}",
                            file, kSamplesAttribute, attribute(kSamplesAttribute),
                            header.part.index, header.part.count, header.totalSamplesPerPixel,
                            expectedSamples);
    header.filter = attribute(kFilterAttribute);
    header.scene = attribute(kSceneAttribute);
    if (!image.channels().count(kWeightChannel))
        throw NoriException("{}: a part without its '{}' channel (the filter weights the merge "
                            "needs)",
                            file, kWeightChannel);
    if (image.hasLayer(aovName(AOV::Variance)) && !image.channels().count(kEvenHalfWeightChannel))
        throw NoriException("{}: a part with a variance layer but no '{}' channel (the "
                            "half-buffer the merge recomputes it from)",
                            file, kEvenHalfWeightChannel);
    return header;
}

RenderResult renderPart(Scene &scene, RenderOptions options, const PartSpec &part,
                        const std::string &sceneHash, const std::string &sceneName) {
    const Sampler &sampler = *scene.getSampler();
    if (sampler.getMaxTolerance() > 0.0f)
        throw NoriException("a render with adaptive sampling (maxTolerance {}) cannot be split "
                            "into parts: where a pixel stops depends on all its earlier samples",
                            sampler.getMaxTolerance());
    if (options.timeBudget > 0.0)
        throw NoriException("a part of a split render takes a fixed slice of the samples: it "
                            "cannot have a time budget");
    const size_t totalSpp =
        options.samplesPerPixel > 0 ? options.samplesPerPixel : sampler.getSampleCount();
    const SampleSlice slice = partSamples(part, totalSpp);
    options.firstSample = slice.first;
    options.samplesPerPixel = slice.count;
    options.keepFilterWeights = true;
    RenderResult result = renderScene(scene, options);
    if (!result.complete)
        return result; // an interrupted part has no header: the merge refuses it

    const ReconstructionFilter *filter = scene.getCamera()->getReconstructionFilter();
    PartHeader header;
    header.part = part;
    header.sceneHash = sceneHash;
    header.resolution = result.layers.size();
    header.totalSamplesPerPixel = totalSpp;
    header.samples = slice;
    header.filter = filter ? filter->toString() : "box (radius 0.5)";
    header.scene = sceneName;
    writePartHeader(header, result.layers);
    return result;
}

MergeResult mergeParts(const std::vector<std::string> &files, bool allowMissing) {
    if (files.empty())
        throw NoriException("merge: no part files given");
    using Sums = Eigen::ArrayXXd;
    std::map<std::string, Sums> sums; // per channel, over the parts so far
    std::map<int, std::string> seen;  // part index → file
    PartHeader first;
    std::string firstFile;
    std::set<std::string> firstChannels;

    for (const std::string &file : files) {
        const LayeredImage part = LayeredImage::loadEXR(file);
        const PartHeader header = readPartHeader(part, file);
        std::set<std::string> channels;
        for (const auto &[name, values] : part.channels())
            channels.insert(name);
        if (firstFile.empty()) {
            first = header;
            firstFile = file;
            firstChannels = channels;
            for (const std::string &name : channels)
                sums[name] = Sums::Zero(header.resolution.y(), header.resolution.x());
        } else {
            const auto differs = [&](const char *what, const std::string &mine,
                                     const std::string &theirs) {
                if (mine != theirs)
                    throw NoriException("{}: {} {} differs from {}'s {}: not a part of the same "
                                        "render",
                                        file, what, mine, firstFile, theirs);
            };
            if (header.sceneHash != first.sceneHash)
                throw NoriException("{}: scene hash {} differs from {}'s {}: a part of another "
                                    "scene (or of the scene after its files or -D definitions "
                                    "changed)",
                                    file, header.sceneHash, firstFile, first.sceneHash);
            differs("total spp", std::to_string(header.totalSamplesPerPixel),
                    std::to_string(first.totalSamplesPerPixel));
            differs("resolution",
                    fmt::format("{}x{}", header.resolution.x(), header.resolution.y()),
                    fmt::format("{}x{}", first.resolution.x(), first.resolution.y()));
            differs("part count N", std::to_string(header.part.count),
                    std::to_string(first.part.count));
            differs("filter", header.filter, first.filter);
            if (channels != firstChannels)
                throw NoriException("{}: channels ({}) differ from {}'s: rendered with other "
                                    "AOV layers",
                                    file, describeChannels(part), firstFile);
        }
        if (const auto other = seen.find(header.part.index); other != seen.end())
            throw NoriException("{}: part {}/{} given twice (also {})", file, header.part.index,
                                header.part.count, other->second);
        seen[header.part.index] = file;

        const LayeredImage::Channel &weight = part.channels().at(kWeightChannel);
        for (const auto &[name, values] : part.channels()) {
            switch (mergeRule(name)) {
            case MergeRule::Weighted:
                sums[name] += values.cast<double>() * weight.cast<double>();
                break;
            case MergeRule::EvenHalf:
                sums[name] += values.cast<double>() *
                              part.channels().at(kEvenHalfWeightChannel).cast<double>();
                break;
            case MergeRule::Summed:
                sums[name] += values.cast<double>();
                break;
            case MergeRule::Recomputed:
                break; // from the sums, once all are in
            }
        }
    }

    MergeResult result;
    result.totalSamplesPerPixel = first.totalSamplesPerPixel;
    result.partCount = first.part.count;
    for (int k = 1; k <= first.part.count; ++k) {
        if (seen.count(k))
            result.samplesPerPixel +=
                partSamples({k, first.part.count}, first.totalSamplesPerPixel).count;
        else
            result.missing.push_back(k);
    }
    if (!result.missing.empty() && !allowMissing)
        throw NoriException("merge: {} of {} parts missing (part{} {}); --allow-missing merges "
                            "the {} given",
                            result.missing.size(), first.part.count,
                            result.missing.size() > 1 ? "s" : "", fmt::join(result.missing, ", "),
                            seen.size());

    // Normalise: the merged film's sums divided by its weights (0 where no weight, as
    // Color4f::divideByFilterWeight does).
    const Sums &weight = sums.at(kWeightChannel);
    const auto mean = [](const Sums &sum, const Sums &w) -> LayeredImage::Channel {
        return (w != 0.0).select(sum / w, 0.0).cast<float>();
    };
    result.image = LayeredImage(first.resolution);
    const bool withHalves = firstChannels.count(std::string(aovName(AOV::Variance)) + ".R") > 0;
    for (const std::string &name : firstChannels) {
        switch (mergeRule(name)) {
        case MergeRule::Weighted:
            result.image.addChannel(name, mean(sums.at(name), weight));
            break;
        case MergeRule::Summed:
            // The filter weights stay with the half-buffer, as in a render (Film::develop).
            if (name != kWeightChannel || withHalves)
                result.image.addChannel(name, sums.at(name).cast<float>());
            break;
        case MergeRule::EvenHalf:
            result.image.addChannel(name, mean(sums.at(name), sums.at(kEvenHalfWeightChannel)));
            break;
        case MergeRule::Recomputed:
            break; // the variance, recomputed below
        }
    }
    if (withHalves) {
        // The variance from the merged half-buffers, as Film::develop computes it.
        const Sums &evenWeight = sums.at(kEvenHalfWeightChannel);
        const std::string even = std::string(kEvenHalfLayer) + ".";
        Bitmap variance(first.resolution);
        for (int y = 0; y < variance.rows(); ++y)
            for (int x = 0; x < variance.cols(); ++x) {
                const auto at = [&](const std::string &name) {
                    return static_cast<float>(sums.at(name)(y, x));
                };
                const Color4f total(Eigen::Array4f(at("R"), at("G"), at("B"), at(kWeightChannel)));
                const Color4f evenSum(Eigen::Array4f(at(even + "R"), at(even + "G"), at(even + "B"),
                                                     float(evenWeight(y, x))));
                variance(y, x) = halfBufferVariance(total, evenSum);
            }
        result.image.addLayer(aovName(AOV::Variance), aovChannels(AOV::Variance), variance);
    }
    result.image.attributes[kHashAttribute] = first.sceneHash;
    result.image.attributes[kSppAttribute] = std::to_string(result.samplesPerPixel);
    result.image.attributes[kFilterAttribute] = first.filter;
    result.image.attributes[kSceneAttribute] = first.scene;
    result.image.attributes["nori.mergedParts"] = fmt::format(
        "{} of {}{}", seen.size(), first.part.count,
        result.missing.empty() ? std::string()
                               : fmt::format(" (missing {})", fmt::join(result.missing, ", ")));
    return result;
}

} // namespace nori
